//! A slew flown in closed loop (issue #30 item 4): the three-axis decomposition's plan
//! ([`super::slew`], seed 000 §10) turned into a reference trajectory (attitude, body rate and
//! the body's feed-forward momentum in time) that the wheels can follow and the quaternion
//! feedback law ([`super::tracking`]) tracks. The two nodes split it: the reference node flies
//! the profiles ([`SlewTrajectory`]) and sends each step's rates ([`SlewReference`]); the
//! attitude node integrates the attitude from them ([`SlewFollower`]) and closes the loop
//! ([`feedback_torque`]).
//!
//! Attitudes follow [`crate::attitude`]: `v_body = A(q) · v_ref`, `q̇ = ½ q ⊗ (0, ω)` with ω in
//! body axes.
//!
//! # Profile
//! Each rotation of the plan (angle `α ≥ 0` about the unit body axis `ê`, its sense in `ê`) is
//! flown with a trapezoidal rate `ṡ`: a ramp at `a = τ/I`, a coast at `ω_p`, a ramp down. `I` is
//! the principal moment about `ê` and `τ` [`TORQUE_FRACTION`] of the smallest of the wheels'
//! torques about the body axes, which they give about any axis (the rest is the feedback's).
//! With the plan's rate `ω_c` and duration `D = α/ω_c`, and `⌈·⌉` rounding up to whole control
//! periods:
//! ```text
//! t_r = ⌈ω_c/a⌉        T = max(⌈D + t_r⌉, 2 t_r)        ω_p = α/(T − t_r)
//! s(u) = ½ ω_p u²/t_r                u < t_r
//!        ω_p (u − t_r/2)             u < T − t_r
//!        α − ½ ω_p (T − u)²/t_r      u < T,      then α
//! ```
//! so `ω_p ≤ ω_c` (the plan's momentum is never exceeded) and `ω_p/t_r ≤ a` (nor the torque; a
//! short rotation, `D < t_r`, ramps up and down without reaching `ω_c`). After each rotation the
//! reference rests for the pause, as the open-loop plan did (a null rotation takes no time and
//! no pause).
//!
//! # What each step carries
//! The profile is linear between whole periods, so the rate at the middle of a period is its
//! mean. A step at `t` carries the mean rate over the period before, `ṡ(t − T/2) ê`, and the
//! feed-forward: the body momentum at the mean rate over the period after, `I ṡ(t + T/2) ê`
//! (wheels holding `H − I ṡ ê`, `H` the total momentum, turn the body by the profile's angle
//! over the period). The follower integrates its attitude from the first, exactly:
//! `q(t) = q(t − T) ⊗ (cos(θ/2), ê sin(θ/2))`, `θ = ṡ(t − T/2) T`, from the attitude estimated
//! when the slew begins (a step without a reference turns on at the last rate, as the wheels,
//! holding their momentum, do).
//!
//! # What the feedback tracks
//! A wheel takes its period's momentum step at its own torque: at the ramps' fraction
//! `f` = [`TORQUE_FRACTION`] of it, that fraction of the period, so the body follows the
//! profile late by `f T/2`. The feedback therefore tracks the follower's attitude turned back
//! by `f T/2` at the last mean rate, and compares the gyros' rate with that mean rate. With
//! these and the tracking law's gains, the loop flew the thesis's slew to 0.039° at the end of
//! its plan in the ideal truth (0.107° open loop; the thesis's Simulink 0.148°); tracking the
//! profile's own attitude and rate at `t` gave 0.122° and, with the realistic truth's gyros (a
//! mean over the period), 0.16–0.33° (`tests/closed_loop.rs`, scratch runs). The thesis
//! scenarios fly the feedback at four times their tracking law's bandwidth
//! (`AcsConfig::slew_gain_factor`), for dispersed inertia.
//!
//! # Accuracy
//! Over 600 random slews (`tests/slew_trajectory.rs`: the flight satellite at 1 s and 0.1 s
//! periods, and one whose principal axes are tilted from its body axes) the follower's
//! attitude ends at the plan's target within 6.6e-6 rad, the feed-forward's mean rates
//! integrate to it within 6.7e-6 rad (f32 rounding over up to 1 200 steps), and neither the
//! plan's rate nor the ramps' torque about any body axis is exceeded (the bounds: 1e-5 rad,
//! 1e-5 rad, a ratio of 1).

use crate::attitude::Quaternion;
use crate::control::magnetorquer::saturate_dipole;
use crate::control::principal_axes::PrincipalAxes;
use crate::control::slew::{SlewError, SlewPlan, SlewStep, NULL_ANGLE_RAD};
use crate::control::tracking::{tracking_torque, TrackingError, TrackingGains};
use crate::fmath;
use crate::linalg::{Mat3, Vec3};

/// The fraction of the wheels' torque about a rotation's axis its ramps ask; the rest is left
/// to the feedback law (which holds the errors the ramps leave and the disturbances).
pub const TORQUE_FRACTION: f32 = 0.5;

/// One rotation of a slew as flown (see the [module docs](self)).
#[derive(Copy, Clone, Debug, PartialEq)]
struct Rotation {
    /// `ê`, unit, body axes, the rotation's sense included (zero for a null rotation).
    axis_body: Vec3,
    /// `I`, the principal moment about `ê`, kg·m².
    moment_kgm2: f32,
    /// `t_r`, s (whole periods).
    ramp_s: f32,
    /// `T`, s (whole periods; 0 for a null rotation).
    duration_s: f32,
    /// `ω_p`, rad/s.
    peak_radps: f32,
}

impl Rotation {
    const NULL: Self = Self {
        axis_body: Vec3::new(0.0, 0.0, 0.0),
        moment_kgm2: 0.0,
        ramp_s: 0.0,
        duration_s: 0.0,
        peak_radps: 0.0,
    };

    /// This rotation flies `step` (see the [module docs](self)) with the moment `I`
    /// (kg·m²), the ramps' acceleration `a` (rad/s², positive) and the period (s), in place; a
    /// null step leaves it null.
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    fn fly(&mut self, step: &SlewStep, moment_kgm2: f32, accel: f32, period_s: f32) {
        let angle = fmath::abs(step.angle_rad);
        let d = step.duration_s;
        if !(angle > NULL_ANGLE_RAD) || !(d > 0.0) {
            return;
        }
        // the step's rate |α|/D along a principal axis: ê = ω D/|α| (no norm)
        // (a short rotation, D < t_r, ramps to less than ω_c: T = 2 t_r, ω_p/t_r = α/t_r² ≤ a)
        let ramp = whole_periods(angle / d / accel, period_s);
        let duration = fmath::max(whole_periods(d + ramp, period_s), ramp + ramp);
        self.axis_body = step.omega_body_radps * (d / angle);
        self.moment_kgm2 = moment_kgm2;
        self.ramp_s = ramp;
        self.duration_s = duration;
        self.peak_radps = angle / (duration - ramp);
    }

    /// `ṡ` at `u` seconds from the rotation's start (clamped to `0 ..= T`). The angle `s`
    /// itself (`½ω_p u²/t_r` on the first ramp, `ω_p (u − ½t_r)` at cruise, `α − ½ω_p v²/t_r`
    /// on the last, `α` after) is not computed: the reference carries rates only.
    fn rate(&self, u: f32) -> f32 {
        let (t_r, t, w) = (self.ramp_s, self.duration_s, self.peak_radps);
        let u = fmath::max(u, 0.0);
        if !(t > u) || !(t_r > 0.0) {
            0.0
        } else if t_r > u {
            w * u / t_r
        } else if t - t_r > u {
            w
        } else {
            let v = t - u;
            w * v / t_r
        }
    }
}

/// A rotation's time with the pause after it, s (a null rotation has neither).
fn with_pause(r: &Rotation, pause_s: f32) -> f32 {
    if r.duration_s > 0.0 {
        r.duration_s + pause_s
    } else {
        0.0
    }
}

/// `x` seconds rounded up to whole periods of `period_s`, at least one.
#[cfg_attr(target_arch = "msp430", inline(never))]
fn whole_periods(x: f32, period_s: f32) -> f32 {
    (fmath::max(x / period_s - 1e-4, 0.0) as u32 + 1) as f32 * period_s
}

/// What the reference node sends of a slew at one time (see the [module docs](self)).
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SlewReference {
    /// The profile's mean rate over the control period before `t`, rad/s (body): what the
    /// body turned at over it, the rate the feedback compares the gyros' with, and what the
    /// follower integrates its attitude with ([`SlewFollower`]).
    #[cfg_attr(feature = "defmt", defmt(Debug2Format))]
    pub rate_body_radps: Vec3,
    /// The feed-forward: the body momentum at the profile's mean rate over the period from
    /// `t`, kg·m²/s (body).
    #[cfg_attr(feature = "defmt", defmt(Debug2Format))]
    pub h_ff_body_nms: Vec3,
}

/// `q ⊗ (cos(θ/2), ê sin(θ/2))` with `θ ê = rotation_rad`: `q` (reference TEME → body) turned
/// by the rotation vector `rotation_rad` (body axes), exactly (`q` itself for a zero one).
///
/// The rotation's quaternion is written out rather than taken from
/// [`Quaternion::from_axis_angle`]: that one's checks and nalgebra norm cost the attitude node
/// 1 554 B of flash (measured), more than its margin.
#[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
pub fn turned(q: &Quaternion, rotation_rad: &Vec3) -> Quaternion {
    let angle = crate::linalg::norm(rotation_rad);
    if !(angle > 0.0) {
        return *q;
    }
    let (sin, cos) = fmath::sincos(0.5 * angle);
    let v = crate::linalg::scale(rotation_rad, sin / angle);
    q.mul(&Quaternion {
        q0: cos,
        q1: v.x,
        q2: v.y,
        q3: v.z,
    })
}

/// The follower's side of a slew (the attitude node): the profile's attitude, integrated
/// from the mean rates the references give (each the rate over the period just flown; see the
/// [module docs](self)), from the attitude estimated when the slew begins; and the momentum the
/// wheels hold beside the feed-forward.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct SlewFollower {
    /// The profile's attitude now (reference TEME → body), once an estimate started it.
    attitude: Option<Quaternion>,
    /// The last reference's mean rate, rad/s (body): held through a step without a reference
    /// (the wheels hold their momentum, the body turns on).
    rate_body_radps: Vec3,
    /// The momentum the wheels hold beside the feed-forward, kg·m²/s (body): theirs when the
    /// slew began, with the feedback's torque integrated.
    h_base_nms: Vec3,
}

impl SlewFollower {
    /// A slew's follower before its first step, the wheels holding `h_wheels_nms` (body,
    /// kg·m²/s).
    pub const fn new(h_wheels_nms: Vec3) -> Self {
        Self {
            attitude: None,
            rate_body_radps: Vec3::new(0.0, 0.0, 0.0),
            h_base_nms: h_wheels_nms,
        }
    }

    /// One step `dt_s` after the last: the profile's attitude moves on by the step's reference
    /// rate (the last one held without a reference); it starts at `estimate` (reference TEME →
    /// body) at the first step with one. Returns the attitude the feedback tracks: the
    /// profile's, turned back by the wheels' lag `f dt/2` (`f` = [`TORQUE_FRACTION`]).
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    pub fn advance(
        &mut self,
        reference: Option<&SlewReference>,
        estimate: Option<&Quaternion>,
        dt_s: f32,
    ) -> Option<Quaternion> {
        if let Some(r) = reference {
            self.rate_body_radps = r.rate_body_radps;
        }
        let w = self.rate_body_radps;
        let attitude = match (&self.attitude, estimate) {
            (Some(q), _) => turned(q, &crate::linalg::scale(&w, dt_s)),
            (None, Some(q)) => *q,
            (None, None) => return None,
        };
        self.attitude = Some(attitude);
        Some(turned(
            &attitude,
            &crate::linalg::scale(&w, -TORQUE_FRACTION * 0.5 * dt_s),
        ))
    }

    /// The feedback's torque `torque_nm` (body, N·m; [`feedback_torque`]) held for `dt_s`,
    /// integrated into the momentum the wheels hold (`ḣ = −τ`).
    pub fn integrate(&mut self, torque_nm: &Vec3, dt_s: f32) {
        self.h_base_nms = crate::linalg::sub_scaled(&self.h_base_nms, torque_nm, dt_s);
    }

    /// The wheels' momentum with `reference`'s feed-forward, kg·m²/s (body): the momentum they
    /// hold less the body's feed-forward momentum.
    pub fn h_wheels_nms(&self, reference: &SlewReference) -> Vec3 {
        crate::linalg::sub(&self.h_base_nms, &reference.h_ff_body_nms)
    }
}

/// The feedback's body torque about the tracked attitude `target` and rate `rate_body_radps`
/// (a [`SlewReference`]'s), N·m: the quaternion feedback law ([`tracking_torque`]) from the
/// estimate `(q, ω)` (reference TEME → body, the gyros' rate), with the wheels' momentum
/// `h_wheels` (body, kg·m²/s), limited per body axis to the `1 −` [`TORQUE_FRACTION`] of
/// `torque_nm` the ramps leave (the direction kept). The caller integrates it into the wheels
/// (`ḣ = −τ`) beside the feed-forward.
#[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
pub fn feedback_torque(
    gains: &TrackingGains,
    inertia_body: &Mat3,
    torque_nm: &Vec3,
    estimate: (&Quaternion, &Vec3),
    target: &Quaternion,
    rate_body_radps: &Vec3,
    h_wheels: &Vec3,
) -> Result<Vec3, TrackingError> {
    let (q, omega) = estimate;
    let tau = tracking_torque(
        gains,
        inertia_body,
        q,
        omega,
        target,
        rate_body_radps,
        h_wheels,
    )?;
    // the coils' per-axis scaling keeping the direction; a limit that is not positive and
    // finite (refused there) leaves the torque as it is
    let limit = crate::linalg::scale(torque_nm, 1.0 - TORQUE_FRACTION);
    Ok(saturate_dipole(&tau, &limit).map_or(tau, |(t, _)| t))
}

/// A slew's reference trajectory (see the [module docs](self)): the rotations' profiles, on the
/// reference node.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct SlewTrajectory {
    /// In execution order (the plan's).
    rotations: [Rotation; 3],
    /// The rest after each rotation, s.
    pause_s: f32,
    /// The rotations (each with its pause) done.
    done: u8,
    /// When rotation `done` starts, s from the slew's start.
    done_s: f32,
}

impl SlewTrajectory {
    /// The trajectory of `plan` (planned with `axes`): the ramps ask [`TORQUE_FRACTION`] of the
    /// smallest of `torque_nm` (the wheels' torque about each body axis, N·m), the times are
    /// whole periods of `period_s`, each rotation followed by `pause_s`.
    /// [`SlewError::InvalidLimits`] if a torque or the period is not positive and finite, or the
    /// pause negative or infinite.
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    pub fn new(
        plan: &SlewPlan,
        axes: &PrincipalAxes,
        torque_nm: &Vec3,
        period_s: f32,
        pause_s: f32,
    ) -> Result<Self, SlewError> {
        // about any axis the wheels give at least their smallest per-axis torque (a NaN `x`
        // makes the minimum NaN, a NaN `y` or `z` the sum)
        let (x, y, z) = (torque_nm.x, torque_nm.y, torque_nm.z);
        let tau = TORQUE_FRACTION * fmath::min(fmath::min(x, y), z);
        let sum = x + y + z + period_s + pause_s;
        if !(tau > 0.0 && period_s > 0.0 && pause_s >= 0.0 && sum.is_finite()) {
            return Err(SlewError::InvalidLimits);
        }
        let mut trajectory = Self {
            rotations: [Rotation::NULL, Rotation::NULL, Rotation::NULL],
            pause_s,
            done: 0,
            done_s: 0.0,
        };
        for (r, step) in trajectory.rotations.iter_mut().zip(plan.steps.iter()) {
            let moment = match step.axis {
                0 => axes.moments.x,
                1 => axes.moments.y,
                _ => axes.moments.z,
            };
            let accel = tau / moment;
            if !(accel > 0.0 && accel.is_finite()) {
                return Err(SlewError::InvalidLimits);
            }
            r.fly(step, moment, accel, period_s);
        }
        Ok(trajectory)
    }

    /// The whole slew's duration, s (each rotation with its pause).
    pub fn duration_s(&self) -> f32 {
        self.rotations
            .iter()
            .map(|r| with_pause(r, self.pause_s))
            .sum()
    }

    /// The reference `t_s` seconds from the slew's start, for the control period `period_s`
    /// that starts then; `None` once the slew is done (its end within half a period: the
    /// times fall on whole periods). The trajectory is asked at increasing times (an earlier
    /// time is taken as the start of the rotation in progress).
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    pub fn at(&mut self, t_s: f32, period_s: f32) -> Option<SlewReference> {
        let t = t_s + 0.5 * period_s;
        let r = loop {
            let r = self.rotations.get(usize::from(self.done))?;
            let end = self.done_s + with_pause(r, self.pause_s);
            if end > t {
                break r;
            }
            self.done += 1;
            self.done_s = end;
        };
        let u = t_s - self.done_s;
        let half = 0.5 * period_s;
        let rate = r.rate(u - half);
        let mean_rate = r.rate(u + half);
        Some(SlewReference {
            rate_body_radps: r.axis_body * rate,
            h_ff_body_nms: r.axis_body * (r.moment_kgm2 * mean_rate),
        })
    }
}
