//! Open-loop slew planning with reaction wheels: the manoeuvre matrix, its three-axis quaternion
//! decomposition about the principal axes, and the angular-momentum commands (seed 000 ch. 10,
//! eqs. 10.7–10.29; note 000 §3.10, §4.3, §4.4, §4.8, §7.10–7.11).
//!
//! Attitudes follow the crate convention ([`crate::attitude`]): `v_body = A · v_ref`.
//!
//! # Symbols
//! | name | thesis | meaning |
//! |---|---|---|
//! | `a` | `A` | current attitude, reference (IJK/TEME) → body UVW |
//! | `a_d` | `A_d` | commanded attitude |
//! | `e` | `E` | principal axes, rows in UVW ([`super::principal_axes`]) |
//! | `m_abc` | `M_abc = E A_d Aᵀ Eᵀ` | the manoeuvre in principal axes (eq. 10.9) |
//! | `phi_a`, `theta_b`, `psi_c` | Φ, θ, Ψ | rotations about A, B, C: `M_abc = A1(Φ) A2(θ) A3(Ψ)`; Ψ first, then θ, then Φ |
//! | `qa`, `qb` | `A`, `B` of eqs. 10.23–10.24 | `q0q1 + q2q3`, `−q0² + q1² + q2² − q3²` |
//! | `q4` | `q''''` | `q ⊗ q'*` = `q''' ⊗ q''` (eq. 10.22) |
//!
//! # Branches
//! [`Branch::Thesis`] takes `Φ = atan(−2A/B)` on the principal branch and `Ψ, θ = 2 atan(·)`:
//! it reproduces the thesis's numbers but can take a long way round (Test 1: 360.3° in all).
//! [`Branch::Shortest`] tries `Φ`, `Φ ± π` and keeps the decomposition with the smallest
//! `|Φ| + |θ| + |Ψ|` (Test 1: 179.7°). Every branch reconstructs `M_abc` exactly (to f32 rounding).
//!
//! # Singular cases
//! - `B = 0`: `Φ = ∓90°` (the limit of `atan(−2A/B)`); `A = B = 0` (θ = ±90°, where Φ and Ψ are
//!   not unique): `Φ = 0` is chosen.
//! - `q0'''' ≈ 0`: the ratios of eq. 10.21 (`tan(Ψ/2) = −q1''''/q2''''`,
//!   `tan(θ/2) = −q1''''/q3''''`); the code always uses whichever pair of components is larger,
//!   so no division by a small number and no NaN can occur.
//!
//! # Accuracy
//! In f32 the angles of the chapter-10 example and of Tests 1 and 2, and the momenta L1..L3,
//! are reproduced within 1e-5 relative (the test's bound; measured worst: 1.3e-7 for the angles,
//! 2.1e-7 for the momenta; `cargo test --test control -- --nocapture` prints them).

use core::f32::consts::{FRAC_PI_2, PI};
use core::fmt;

use crate::attitude::{Dcm, Quaternion};
use crate::control::principal_axes::PrincipalAxes;
use crate::fmath;
use crate::linalg::{mat_mul, mat_vec, transpose, Mat3, Vec3};

/// Which solution of `tan Φ = −2A/B` to take.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Branch {
    /// The thesis's principal value `Φ = atan(−2A/B)` (reproduces its numbers).
    Thesis,
    /// The decomposition with the smallest total rotation `|Φ| + |θ| + |Ψ|`.
    Shortest,
}

/// The three rotations of a slew about the principal axes, radians:
/// `M_abc = A1(phi_a) · A2(theta_b) · A3(psi_c)`, performed Ψ (about C) first, then θ (about B),
/// then Φ (about A).
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct AxisAngles {
    /// Φ, the third rotation, about principal axis A, rad.
    pub phi_a: f32,
    /// θ, the second rotation, about principal axis B, rad.
    pub theta_b: f32,
    /// Ψ, the first rotation, about principal axis C, rad.
    pub psi_c: f32,
}

impl AxisAngles {
    /// `|Φ| + |θ| + |Ψ|`, rad.
    pub fn total_rad(&self) -> f32 {
        fmath::abs(self.phi_a) + fmath::abs(self.theta_b) + fmath::abs(self.psi_c)
    }

    /// The matrix `A1(Φ) · A2(θ) · A3(Ψ)` these angles describe.
    pub fn to_matrix(&self) -> Mat3 {
        let m = Dcm::a3(self.psi_c)
            .then(&Dcm::a2(self.theta_b))
            .then(&Dcm::a1(self.phi_a));
        *m.matrix()
    }
}

/// Errors of the slew planner.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum SlewError {
    /// An input is NaN or infinite.
    NotFinite,
    /// A limit is not positive or the limits are inconsistent (`l_min > l_max`).
    InvalidLimits,
    /// The momentum a rotation needs to last `t_min` is below the wheels' smallest usable
    /// momentum: `axis` (0 = A, 1 = B, 2 = C), the momentum needed, kg·m²/s.
    BelowMinimumMomentum {
        /// Principal axis index, 0 = A, 1 = B, 2 = C.
        axis: u8,
        /// The momentum the rotation would need, kg·m²/s.
        needed: f32,
    },
    /// The slew cannot be done within the commanded time even at the maximum momentum:
    /// the shortest total duration achievable, s.
    TooSlow {
        /// The shortest total duration at `l_max`, s.
        shortest_s: f32,
    },
    /// A principal axis has no working wheel to carry its rotation (axis 0 = A, 1 = B, 2 = C).
    NoWheel {
        /// Principal axis index.
        axis: u8,
    },
}

impl fmt::Display for SlewError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotFinite => write!(f, "slew input is NaN or infinite"),
            Self::InvalidLimits => write!(f, "slew limits are not positive or l_min > l_max"),
            Self::BelowMinimumMomentum { axis, needed } => write!(
                f,
                "rotation about axis {axis} needs {needed} kg·m²/s, below the minimum usable"
            ),
            Self::TooSlow { shortest_s } => {
                write!(f, "slew needs at least {shortest_s} s, more than commanded")
            }
            Self::NoWheel { axis } => write!(f, "no working wheel for principal axis {axis}"),
        }
    }
}

/// The manoeuvre matrix `M_abc = E · A_d · Aᵀ · Eᵀ` (eqs. 10.7 and 10.9): the commanded
/// principal axes relative to the current ones. `a` and `a_d` follow [`crate::attitude`].
#[cfg_attr(target_arch = "msp430", optimize(size))]
pub fn manoeuvre_matrix(a: &Dcm, a_d: &Dcm, axes: &PrincipalAxes) -> Mat3 {
    let a_uvw = mat_mul(a_d.matrix(), &transpose(a.matrix()));
    mat_mul(&mat_mul(&axes.e, &a_uvw), &transpose(&axes.e))
}

/// Decomposes a rotation `m_abc` into `A1(Φ) A2(θ) A3(Ψ)` by quaternion factorisation
/// (eqs. 10.10–10.24, note 000 §3.10 step 2) on the chosen [`Branch`].
#[cfg_attr(target_arch = "msp430", optimize(size))]
pub fn decompose(m_abc: &Mat3, branch: Branch) -> Result<AxisAngles, SlewError> {
    if m_abc.iter().any(|x| !x.is_finite()) {
        return Err(SlewError::NotFinite);
    }
    let q = Dcm::from_matrix_unchecked(*m_abc).to_quaternion();
    // eqs. 10.23–10.24: A(q0'² − q1'²) + B q0' q1' = 0  ⇔  tan Φ = −2A/B
    let qa = q.q0 * q.q1 + q.q2 * q.q3;
    let qb = -q.q0 * q.q0 + q.q1 * q.q1 + q.q2 * q.q2 - q.q3 * q.q3;
    let phi_principal = if qb != 0.0 {
        fmath::atan(-2.0 * qa / qb)
    } else if qa != 0.0 {
        // limit of atan(−2A/B) as B → 0
        if qa > 0.0 {
            -FRAC_PI_2
        } else {
            FRAC_PI_2
        }
    } else {
        // θ = ±90°: Φ and Ψ are not unique; Φ = 0 is chosen
        0.0
    };
    match branch {
        Branch::Thesis => Ok(factor_given_phi(&q, phi_principal)),
        Branch::Shortest => {
            let candidates = [phi_principal, phi_principal + PI, phi_principal - PI];
            let mut best = factor_given_phi(&q, phi_principal);
            for phi in candidates.iter().skip(1) {
                let c = factor_given_phi(&q, wrap_pi(*phi));
                if best.total_rad() > c.total_rad() {
                    best = c;
                }
            }
            Ok(best)
        }
    }
}

/// `x` wrapped to (−π, π], for |x| ≤ 3π (the candidates `Φ ± π` of [`decompose`], with
/// `Φ ∈ [−π/2, π/2]`): one addition of the f32 2π at most (no general reduction, whose
/// large-argument path links a 64-bit remainder into the flight image).
fn wrap_pi(x: f32) -> f32 {
    if x > PI {
        x - 2.0 * PI
    } else if !(x > -PI) {
        x + 2.0 * PI
    } else {
        x
    }
}

/// Steps 3–5 of the factorisation for a given Φ: `q'''' = q ⊗ q'*`, then Ψ and θ from
/// `2·atan` of a component ratio (the thesis's form, eqs. 10.17–10.21), so Ψ, θ ∈ (−π, π].
#[cfg_attr(target_arch = "msp430", optimize(size))]
fn factor_given_phi(q: &Quaternion, phi: f32) -> AxisAngles {
    let (s1, c1) = fmath::sincos(0.5 * phi);
    let q_prime = Quaternion {
        q0: c1,
        q1: s1,
        q2: 0.0,
        q3: 0.0,
    };
    // eq. 10.22: q'''' = q ⊗ q'*
    let q4 = q.mul(&q_prime.conjugate());
    // q'''' = q''' ⊗ q'' = (c3 c2, −s3 s2, c3 s2, c2 s3) (eq. 10.15)
    // Ψ/2 from (q3, q0) = c2·(s3, c3), or from (−q1, q2) = s2·(s3, c3) when c2 is small
    let psi_half = half_angle((q4.q3, q4.q0), (-q4.q1, q4.q2));
    // θ/2 from (q2, q0) = c3·(s2, c2), or from (−q1, q3) = s3·(s2, c2) when c3 is small
    let theta_half = half_angle((q4.q2, q4.q0), (-q4.q1, q4.q3));
    AxisAngles {
        phi_a: phi,
        theta_b: 2.0 * theta_half,
        psi_c: 2.0 * psi_half,
    }
}

/// `atan(num/den)` from whichever of two proportional `(num, den)` pairs is larger (eq. 10.21),
/// ±π/2 when the denominator is zero: never a division by a small number, never NaN.
#[cfg_attr(target_arch = "msp430", optimize(size))]
fn half_angle(pair_a: (f32, f32), pair_b: (f32, f32)) -> f32 {
    let size = |(n, d): (f32, f32)| fmath::abs(n) + fmath::abs(d);
    let (num, den) = if size(pair_a) >= size(pair_b) {
        pair_a
    } else {
        pair_b
    };
    if den != 0.0 {
        fmath::atan(num / den)
    } else if num >= 0.0 {
        FRAC_PI_2
    } else {
        -FRAC_PI_2
    }
}

/// Limits of the momentum planner (note 000 §3.10 step 3). The thesis gives no values; its
/// tests imply `t_min = 0.3 s` and momenta large enough that every rotation hit `t_min`.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SlewLimits {
    /// Maximum angular momentum of one wheel, kg·m²/s.
    pub l_max: f32,
    /// Smallest usable angular momentum of one rotation, kg·m²/s.
    pub l_min: f32,
    /// Shortest duration of one rotation, s.
    pub t_min: f32,
    /// Fraction of `l_max` used by default (the thesis: 0.85, "15 % less than the maximum").
    pub default_fraction: f32,
    /// Number of working wheels that serve each principal axis A, B, C (the thesis counts the
    /// wheels on the nearest body axis, both senses).
    pub wheels_per_axis: [u8; 3],
}

/// One constant-momentum rotation of a slew.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SlewStep {
    /// Principal axis: 0 = A, 1 = B, 2 = C.
    pub axis: u8,
    /// Rotation angle, rad.
    pub angle_rad: f32,
    /// Duration, s (0 for a null rotation).
    pub duration_s: f32,
    /// Body rate during the step, rad/s, body UVW: `Eᵀ ω_abc` (eq. 10.28).
    #[cfg_attr(feature = "defmt", defmt(Debug2Format))]
    pub omega_body_radps: Vec3,
}

impl SlewStep {
    /// Body angular momentum during the step, kg·m²/s, body UVW: `I · ω_uvw` (eq. 10.29), `I`
    /// the inertia of the `axes` it was planned with. The wheels hold the opposite momentum.
    /// (Computed on demand: the flight guidance flies the rate ([`super::slew_trajectory`]).)
    pub fn h_body(&self, axes: &PrincipalAxes) -> Vec3 {
        mat_vec(&axes.inertia_body, &self.omega_body_radps)
    }
}

/// A planned slew: three steps in execution order (about C, then B, then A).
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SlewPlan {
    /// The decomposition the plan executes.
    pub angles: AxisAngles,
    /// Steps in execution order: `steps[0]` about C, `steps[1]` about B, `steps[2]` about A.
    pub steps: [SlewStep; 3],
}

impl SlewPlan {
    /// Total duration of the slew, s.
    pub fn duration_s(&self) -> f32 {
        self.steps.iter().map(|s| s.duration_s).sum()
    }
}

/// The step that rotates by `angle_rad` about principal axis `axis` (0 = A, 1 = B, 2 = C) in
/// `duration_s` (eqs. 10.27–10.28): `ω_abc` along the axis, `ω_uvw = Eᵀ ω_abc` (its momentum,
/// eq. 10.29: [`SlewStep::h_body`]). A zero duration gives a null step.
#[cfg_attr(target_arch = "msp430", optimize(size))]
pub fn step_for(axes: &PrincipalAxes, axis: u8, angle_rad: f32, duration_s: f32) -> SlewStep {
    let rate = if duration_s > 0.0 {
        angle_rad / duration_s
    } else {
        0.0
    };
    let omega_abc = match axis {
        0 => Vec3::new(rate, 0.0, 0.0),
        1 => Vec3::new(0.0, rate, 0.0),
        _ => Vec3::new(0.0, 0.0, rate),
    };
    SlewStep {
        axis,
        angle_rad,
        duration_s,
        omega_body_radps: mat_vec(&transpose(&axes.e), &omega_abc),
    }
}

/// Plans a slew from `angles` within `command_time_s` by the thesis's timing logic (note 000
/// §3.10 step 3):
/// 1. per axis `L = f · l_max · n_wheels` with `f = default_fraction`, `t = |angle| I_k / L`;
/// 2. a rotation shorter than `t_min` is stretched to `t_min` with `L = |angle| I_k / t_min`,
///    and fails with [`SlewError::BelowMinimumMomentum`] if that is below `l_min`;
/// 3. if the total exceeds `command_time_s`, everything is redone with `f = 1`; if it still
///    exceeds it, [`SlewError::TooSlow`].
///
/// A null rotation (|angle| ≤ [`NULL_ANGLE_RAD`]) takes no time and no momentum (a decision:
/// the thesis would report it as below `l_min`; the f32 decomposition of a rotation about one
/// principal axis leaves ~1e-8 rad on the other two, which must not make the slew fail).
#[cfg_attr(target_arch = "msp430", optimize(size))]
pub fn plan(
    axes: &PrincipalAxes,
    angles: &AxisAngles,
    limits: &SlewLimits,
    command_time_s: f32,
) -> Result<SlewPlan, SlewError> {
    let finite = [
        angles.phi_a,
        angles.theta_b,
        angles.psi_c,
        command_time_s,
        limits.l_max,
        limits.l_min,
        limits.t_min,
        limits.default_fraction,
    ]
    .iter()
    .all(|x| x.is_finite());
    if !finite {
        return Err(SlewError::NotFinite);
    }
    if !(limits.l_max > 0.0)
        || !(limits.l_min >= 0.0)
        || limits.l_min > limits.l_max
        || !(limits.t_min >= 0.0)
        || !(limits.default_fraction > 0.0)
        || limits.default_fraction > 1.0
    {
        return Err(SlewError::InvalidLimits);
    }
    let first = durations(axes, angles, limits, limits.default_fraction)?;
    let chosen = if command_time_s >= first.iter().sum::<f32>() {
        first
    } else {
        let fast = durations(axes, angles, limits, 1.0)?;
        let total: f32 = fast.iter().sum();
        if total > command_time_s {
            return Err(SlewError::TooSlow { shortest_s: total });
        }
        fast
    };
    let [t_a, t_b, t_c] = chosen;
    Ok(SlewPlan {
        angles: *angles,
        steps: [
            step_for(axes, 2, angles.psi_c, t_c),
            step_for(axes, 1, angles.theta_b, t_b),
            step_for(axes, 0, angles.phi_a, t_a),
        ],
    })
}

/// Rotations about a principal axis up to this angle are null in [`plan`], rad (1e-5 rad = 2″:
/// a hundred times below the attitude the loop determines, a hundred times above the f32
/// round-off of [`decompose`]).
pub const NULL_ANGLE_RAD: f32 = 1e-5;

/// Durations `[t_A, t_B, t_C]` with momentum fraction `fraction` of `l_max` per wheel.
#[cfg_attr(target_arch = "msp430", optimize(size))]
fn durations(
    axes: &PrincipalAxes,
    angles: &AxisAngles,
    limits: &SlewLimits,
    fraction: f32,
) -> Result<[f32; 3], SlewError> {
    let per_axis = [
        (angles.phi_a, axes.moments.x),
        (angles.theta_b, axes.moments.y),
        (angles.psi_c, axes.moments.z),
    ];
    let mut out = [0.0f32, 0.0, 0.0];
    for (k, ((angle, moment), (t, wheels))) in per_axis
        .iter()
        .zip(out.iter_mut().zip(limits.wheels_per_axis.iter()))
        .enumerate()
    {
        let axis = k as u8;
        if !(fmath::abs(*angle) > NULL_ANGLE_RAD) {
            continue;
        }
        if *wheels == 0 {
            return Err(SlewError::NoWheel { axis });
        }
        let l = fraction * limits.l_max * f32::from(*wheels);
        let needed_t = fmath::abs(*angle) * moment / l;
        *t = if limits.t_min > needed_t {
            let l_stretched = fmath::abs(*angle) * moment / limits.t_min;
            if limits.l_min > l_stretched {
                return Err(SlewError::BelowMinimumMomentum {
                    axis,
                    needed: l_stretched,
                });
            }
            limits.t_min
        } else {
            needed_t
        };
    }
    Ok(out)
}
