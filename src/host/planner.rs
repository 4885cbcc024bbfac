//! Ground-side attitude trajectory planner of seed 001 (Donati 2010, ch. 4–6; note 001 §3):
//! **inverse dynamics** with a spline of the quaternion vector part, Nelder–Mead on the interior
//! knot ordinates, open-loop simulation of each candidate, end-point penalty cost.
//!
//! One candidate (parameters `p` = vector parts `q_v` of the interior knots, 3 per knot):
//! 1. the on-board profile [`AttitudeSpline`] through `q_start`, the interior knots and `q_end`
//!    (uniform knots unless [`Problem::variable_grid`], clamped rest-to-rest ends; f32, exactly
//!    what the spacecraft would evaluate);
//! 2. at each time, ω, ω̇ from it and `τ_id = I ω̇ + ω × I ω` (seed 001 eq. 2.31); the field in body
//!    axes of the **planned** attitude; the dipole by [`crate::planning::allocation::magnetic`]
//!    (per-axis clip, as the thesis) or, with wheels, [`crate::planning::allocation::hybrid`];
//! 3. the true dynamics (seed 001 eq. 2.44, f64, RK4, wheel torque and speed limits) driven by
//!    these commands, open loop, in the seed-001 field (tilted dipole rotating with the Earth,
//!    eqs. 2.34–2.36 with the note's fixes) or IGRF ([`Field`]) along the circular orbit
//!    (eq. 2.37);
//! 4. cost `c_q |δq|² + c_ω |δω|² + c_τ ∫|τ_lost|² dt` (eqs. 6.4–6.7; δω in rad/s,
//!    δq the vector part of the error quaternion).
//!
//! The optimiser is a small bounded Nelder–Mead written here ([`nelder_mead`], coefficients
//! 1, 2, ½, ½ and fminsearch's initial simplex, note 001 §3.7), restarted from its best point,
//! or the compass [`pattern_search`] (Algorithm 2); no extra dependency. Also: **direct
//! dynamics** ([`simulate_direct`]: the dipole splined per axis, cost 6.3/6.5), the variable
//! knot grid of Table 6.5 for both ([`Problem::variable_grid`]), and the minimum-time scaling
//! of eqs. 4.8–4.10 ([`simulate_time_scaled`], [`plan_minimum_time`]).
//!
//! Attitudes follow [`crate::attitude`] (scalar-first, `v_body = A(q) v_ref`).
#![allow(clippy::needless_range_loop)] // fixed 3/4/10-element state arithmetic reads best indexed

use crate::attitude::Quaternion;
use crate::control::wheels::Wheel;
use crate::env::igrf::{Degree, Igrf, FULL};
use crate::linalg::Vec3;
use crate::planning::allocation::{hybrid, magnetic, DipoleSaturation};
use crate::planning::spline::AttitudeSpline;
use crate::time::{gmst_rad_f64, Epoch, TimeSpan, Utc};

/// Largest number of spline knots of a plan.
pub const MAX_KNOTS: usize = 16;

/// μ⊕, km³/s² (used only for the circular-orbit rate).
const MU_KM3_S2: f64 = 398_600.441_8;
/// Dipole strength of seed 001 (eq. 2.36, Plett), Wb·m, over μ0/4π → T·m³.
const MU_F: f64 = 7.9e15;
/// Dipole coelevation and east longitude, seed 001 §2.4.3.
const THETA_M_DEG: f64 = 168.8;
const PHI_M_DEG: f64 = 109.3;
/// Earth rotation rate (360.9856469 deg/day), rad/s.
const OMEGA_EARTH: f64 = 360.985_646_9 / 86_400.0 * core::f64::consts::PI / 180.0;

/// Reaction wheels along the three body axes (seed 001 Table 6.2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wheels {
    /// Rotor inertia, kg·m².
    pub inertia_kgm2: f64,
    /// Speed limit, rad/s.
    pub max_speed_radps: f64,
    /// Motor torque limit, N·m.
    pub max_torque_nm: f64,
}

/// A rest-to-rest manoeuvre to plan.
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    /// Principal inertia, kg·m².
    pub inertia_kgm2: [f64; 3],
    /// Coil limit per axis, A·m².
    pub m_max_am2: f64,
    /// Optional wheels (hybrid allocation, magnetorquers first).
    pub wheels: Option<Wheels>,
    /// Circular orbit radius, km.
    pub a_km: f64,
    /// Orbital rate, rad/s (`None`: `√(μ/a³)`; seed 001 Table 6.1 gives 1.1190e-3, which
    /// note 001 §1.9's field values use).
    pub omega0_radps: Option<f64>,
    /// Inclination, rad.
    pub inc_rad: f64,
    /// Greenwich angle α_G0 at the start (t = 0 at the ascending node), rad (not given by
    /// seed 001: an assumption).
    pub greenwich0_rad: f64,
    /// Start and end attitudes ([`crate::attitude`]; `q0 > 0`).
    pub q_start: Quaternion,
    /// End attitude.
    pub q_end: Quaternion,
    /// Duration, s.
    pub duration_s: f64,
    /// Number of knots (≥ 3: 2 ends + interior).
    pub knots: usize,
    /// Integration step, s.
    pub dt_s: f64,
    /// Cost weights `c_q`, `c_ω` (rad/s), `c_τ`.
    pub weights: [f64; 3],
    /// Geomagnetic field model along the orbit.
    pub field: Field,
    /// Variable time grid (seed 001 Table 6.5): the interior knot abscissae are optimised too.
    /// The parameter vector then ends with one gap parameter `g_i` per interior knot; the gaps
    /// between successive knots are weighted `w_i = g_i² + 0.01` (the last gap fixed at
    /// `w = 0.26`) and scaled to sum to `duration_s`. Whatever the optimiser proposes the knots
    /// stay strictly increasing inside `(0, duration_s)` (every gap positive; at least
    /// `0.01 / (1.01 · (knots − 2) + 0.26)` of the duration while `|g_i| ≤ 1`, the planner's
    /// bounds), and `g_i = 0.5` is the uniform grid (inside the bounds, so Nelder–Mead's first
    /// simplex moves it).
    pub variable_grid: bool,
}

/// Geomagnetic field model of a [`Problem`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Field {
    /// Seed 001's tilted dipole rotating with the Earth ([`dipole_field_t`], with
    /// [`Problem::greenwich0_rad`]): the thesis reproduction.
    Dipole,
    /// IGRF ([`crate::env::igrf::FULL`], degree 13) with the planner's inertial frame taken as
    /// TEME and the Earth angle from the GMST (IAU-82) of `start + t` (UT1 = UTC);
    /// [`Problem::greenwich0_rad`] is not used. `start` is the UTC epoch of `t = 0` (the
    /// ascending node).
    Igrf {
        /// UTC epoch of `t = 0`.
        start: Epoch<Utc>,
    },
    /// Field samples (inertial = TEME, nT) every `step_s` from `t = 0`, linearly interpolated;
    /// e.g. the simulator's truth field along its orbit ([`crate::host::sim::plan_flight`]).
    /// The circular orbit is not used.
    Sampled {
        /// Sample spacing, s.
        step_s: f64,
        /// Samples at `0, step_s, 2 step_s, …`.
        b_teme_nt: Vec<[f64; 3]>,
    },
}

/// Linear interpolation of `samples` spaced `step_s` at `t_s` (error outside them).
fn sampled_field_nt(step_s: f64, samples: &[[f64; 3]], t_s: f64) -> Result<[f64; 3], String> {
    let x = t_s / step_s;
    let outside = || format!("t = {t_s} s outside the {} field samples", samples.len());
    if !(x.is_finite() && x >= 0.0 && x <= samples.len() as f64) {
        return Err(outside());
    }
    let k = x.floor() as usize;
    let f = x - k as f64;
    let a = samples.get(k).ok_or_else(outside)?;
    let b = samples.get(k + 1).unwrap_or(a);
    Ok([
        a[0] + f * (b[0] - a[0]),
        a[1] + f * (b[1] - a[1]),
        a[2] + f * (b[2] - a[2]),
    ])
}

/// IGRF field (TEME, nT) at `r_km` (TEME) at the UTC epoch `start + t_s`.
fn igrf_field_nt(start: &Epoch<Utc>, t_s: f64, r_km: &[f64; 3]) -> Result<[f64; 3], String> {
    let span = TimeSpan::from_seconds_f64(t_s).map_err(|e| format!("t = {t_s} s: {e}"))?;
    let epoch = start.add(span);
    let gmst = gmst_rad_f64(&epoch.to_ut1(None).map_err(|e| e.to_string())?);
    let model = Igrf::at_epoch(&FULL, &epoch, Degree::FULL).map_err(|e| e.to_string())?;
    let b = model
        .teme(&v3(*r_km), gmst as f32)
        .map_err(|e| e.to_string())?;
    Ok(arr(&b))
}

/// Inertial field (T) of seed 001's dipole at the time `t_s` and position `r_km`.
pub fn dipole_field_t(greenwich0_rad: f64, t_s: f64, r_km: &[f64; 3]) -> [f64; 3] {
    let th = THETA_M_DEG.to_radians();
    let am = greenwich0_rad + OMEGA_EARTH * t_s + PHI_M_DEG.to_radians();
    let m = [th.sin() * am.cos(), th.sin() * am.sin(), th.cos()];
    let r = (r_km[0] * r_km[0] + r_km[1] * r_km[1] + r_km[2] * r_km[2]).sqrt();
    let rh = [r_km[0] / r, r_km[1] / r, r_km[2] / r];
    let r_m = r * 1e3;
    let k = MU_F / (r_m * r_m * r_m);
    let d = m[0] * rh[0] + m[1] * rh[1] + m[2] * rh[2];
    [
        k * (3.0 * d * rh[0] - m[0]),
        k * (3.0 * d * rh[1] - m[1]),
        k * (3.0 * d * rh[2] - m[2]),
    ]
}

impl Problem {
    /// Position on the circular orbit (seed 001 eq. 2.37), km.
    pub fn position_km(&self, t_s: f64) -> [f64; 3] {
        let w0 = self
            .omega0_radps
            .unwrap_or_else(|| (MU_KM3_S2 / self.a_km.powi(3)).sqrt());
        let u = w0 * t_s;
        [
            self.a_km * u.cos(),
            self.a_km * u.sin() * self.inc_rad.cos(),
            self.a_km * u.sin() * self.inc_rad.sin(),
        ]
    }

    /// Inertial field in nT at `t_s` from [`Problem::field`].
    ///
    /// Errors (IGRF only): the date out of the model's range, a position below the surface,
    /// non-finite input.
    pub fn field_nt(&self, t_s: f64) -> Result<[f64; 3], String> {
        let r_km = self.position_km(t_s);
        match &self.field {
            Field::Dipole => {
                let b = dipole_field_t(self.greenwich0_rad, t_s, &r_km);
                Ok([b[0] * 1e9, b[1] * 1e9, b[2] * 1e9])
            }
            Field::Igrf { start } => igrf_field_nt(start, t_s, &r_km),
            Field::Sampled { step_s, b_teme_nt } => sampled_field_nt(*step_s, b_teme_nt, t_s),
        }
    }

    /// Number of free parameters (3 per interior knot, plus 1 per interior knot with
    /// [`Problem::variable_grid`]).
    pub fn n_params(&self) -> usize {
        let per_knot = if self.variable_grid { 4 } else { 3 };
        per_knot * self.knots.saturating_sub(2)
    }

    /// Knot abscissae, s: uniform, or from the gap parameters `g` of
    /// [`Problem::variable_grid`] (one per interior knot).
    pub fn knot_times(&self, g: &[f64]) -> Vec<f64> {
        let n = self.knots.saturating_sub(1).max(1);
        if !self.variable_grid {
            return (0..=n)
                .map(|k| self.duration_s * k as f64 / n as f64)
                .collect();
        }
        let w: Vec<f64> = g
            .iter()
            .map(|g| g * g + 0.01)
            .chain(core::iter::once(0.26))
            .collect();
        let total: f64 = w.iter().sum();
        let mut t = vec![0.0];
        let mut acc = 0.0;
        for wi in &w[..w.len() - 1] {
            acc += wi;
            t.push(self.duration_s * acc / total);
        }
        t.push(self.duration_s);
        t
    }

    /// Straight line in `q_v` from start to end (note 001 §4's naive guess).
    pub fn initial_guess(&self) -> Vec<f64> {
        let (a, b) = (self.q_start, self.q_end);
        let n = self.knots - 1;
        let grid = if self.variable_grid { n - 1 } else { 0 };
        (1..n)
            .flat_map(|k| {
                let f = k as f64 / n as f64;
                [
                    a.q1 as f64 + f * (b.q1 - a.q1) as f64,
                    a.q2 as f64 + f * (b.q2 - a.q2) as f64,
                    a.q3 as f64 + f * (b.q3 - a.q3) as f64,
                ]
            })
            .chain(core::iter::repeat_n(0.5, grid))
            .collect()
    }

    /// The profile of the parameters `p`.
    pub fn profile(&self, p: &[f64]) -> Result<AttitudeSpline<MAX_KNOTS>, String> {
        if self.knots < 2 || self.knots > MAX_KNOTS || p.len() != self.n_params() {
            return Err(format!("{} knots / {} parameters", self.knots, p.len()));
        }
        let m = 3 * (self.knots - 2);
        let times: Vec<f32> = self
            .knot_times(&p[m..])
            .into_iter()
            .map(|t| t as f32)
            .collect();
        let mut qs = vec![self.q_start];
        for c in p[..m].chunks(3) {
            let v = Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32);
            let s = 1.0 - v.norm_squared();
            if s <= 1e-6 {
                return Err("interior knot with |q_v| >= 1".into());
            }
            qs.push(Quaternion {
                q0: s.sqrt(),
                q1: v.x,
                q2: v.y,
                q3: v.z,
            });
        }
        qs.push(self.q_end);
        AttitudeSpline::new(&times, &qs, &Vec3::zeros(), &Vec3::zeros()).map_err(|e| e.to_string())
    }
}

/// Commands at one time: dipole (A·m²), wheel motor torques ḣ (N·m), lost torque along b,
/// planned attitude and rate.
#[derive(Clone, Copy, Debug)]
pub struct Command {
    /// Dipole, A·m², body.
    pub dipole_am2: [f64; 3],
    /// Wheel motor torques ḣ, N·m (zero without wheels).
    pub wheel_torque_nm: [f64; 3],
    /// `|τ_lost|²`, N²·m².
    pub lost2: f64,
    /// Planned attitude.
    pub q_plan: Quaternion,
    /// Planned body rate, rad/s.
    pub omega_plan: [f64; 3],
}

fn v3(a: [f64; 3]) -> Vec3 {
    Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32)
}

fn arr(v: &Vec3) -> [f64; 3] {
    [v.x as f64, v.y as f64, v.z as f64]
}

/// The commands at `t_s` of the profile, with the wheels' current total momentum `h_rw`.
pub fn command(
    pb: &Problem,
    plan: &AttitudeSpline<MAX_KNOTS>,
    t_s: f64,
    h_rw: &[f64; 3],
) -> Result<Command, String> {
    let (_, t_end) = plan.interval();
    let t = (t_s as f32).min(t_end);
    let s = plan.sample(t).map_err(|e| e.to_string())?;
    let inertia = crate::linalg::Mat3::from_diagonal(&v3(pb.inertia_kgm2));
    let w = s.omega_radps;
    let tau = inertia * s.omega_dot_radps2 + w.cross(&(inertia * w));
    let b_body = s.jet.q.to_dcm().to_body(&v3(pb.field_nt(t_s)?));
    let m_max = Vec3::repeat(pb.m_max_am2 as f32);
    let (mag, wheel) = match pb.wheels {
        None => (
            magnetic(&tau, &b_body, &m_max, DipoleSaturation::PerAxisClip)
                .map_err(|e| e.to_string())?,
            [0.0; 3],
        ),
        Some(wh) => {
            let set = [Vec3::x(), Vec3::y(), Vec3::z()].map(|a| Wheel {
                axis_body: a,
                limit: wh.max_torque_nm as f32,
                working: true,
            });
            let a = hybrid(
                &tau,
                &b_body,
                &m_max,
                DipoleSaturation::PerAxisClip,
                &set,
                &v3(*h_rw),
                &w,
            )
            .map_err(|e| e.to_string())?;
            (a.magnetic, a.wheel_torque_nm.map(|x| x as f64))
        }
    };
    Ok(Command {
        dipole_am2: arr(&mag.dipole_am2),
        wheel_torque_nm: wheel,
        lost2: mag.lost_along_b_nm.norm_squared() as f64,
        q_plan: s.jet.q,
        omega_plan: arr(&w),
    })
}

/// One sample of a simulated plan.
#[derive(Clone, Copy, Debug)]
pub struct Sample {
    /// Time, s.
    pub t_s: f64,
    /// Simulated attitude `[q0, q1, q2, q3]`.
    pub q: [f64; 4],
    /// Simulated body rate, rad/s.
    pub omega: [f64; 3],
    /// Wheel momenta, kg·m²/s.
    pub h_rw: [f64; 3],
    /// Commands at this time.
    pub cmd: Command,
}

/// Final errors and cost of a simulated plan.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outcome {
    /// Final attitude error, deg (rotation angle between simulated and target).
    pub attitude_error_deg: f64,
    /// Final rate error `|δω|`, deg/s.
    pub rate_error_degps: f64,
    /// Cost (eqs. 6.4–6.7).
    pub cost: f64,
    /// `∫|τ_lost|² dt`, N²·m²·s.
    pub lost_integral: f64,
    /// Largest |m_i|, A·m².
    pub max_dipole_am2: f64,
    /// Largest |ω_rw|, rad/s.
    pub max_wheel_speed_radps: f64,
}

fn qmul(p: [f64; 4], r: [f64; 4]) -> [f64; 4] {
    [
        p[0] * r[0] - p[1] * r[1] - p[2] * r[2] - p[3] * r[3],
        p[1] * r[0] + p[2] * r[3] - p[3] * r[2] + p[0] * r[1],
        -p[1] * r[3] + p[2] * r[0] + p[3] * r[1] + p[0] * r[2],
        p[1] * r[2] - p[2] * r[1] + p[3] * r[0] + p[0] * r[3],
    ]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Passive `A(q) v` in f64 ([`crate::attitude`] matrix).
fn to_body(q: [f64; 4], v: [f64; 3]) -> [f64; 3] {
    // A(q) v = (q* ⊗ (0,v) ⊗ q)_v for the Hamilton product with A(p⊗r) = A(r)A(p)
    let qc = [q[0], -q[1], -q[2], -q[3]];
    let r = qmul(qmul(qc, [0.0, v[0], v[1], v[2]]), q);
    [r[1], r[2], r[3]]
}

type State = [f64; 10];

/// Simulates the plan `p` (RK4, f64) and returns the samples (every `record_every` steps; 0:
/// none) and the outcome.
pub fn simulate(
    pb: &Problem,
    p: &[f64],
    record_every: usize,
) -> Result<(Outcome, Vec<Sample>), String> {
    let plan = pb.profile(p)?;
    run(pb, |t, h| command(pb, &plan, t, h), record_every, false)
}

/// Simulates the plan `p` of `pb` in seed 001's **scaled time** (minimum-time problems,
/// eqs. 4.7–4.10, note 001 §1.11, after Liang, Fullmer & Chen 2004): the state gains the real
/// time `x8` and the scale factor `x9 = scale`; over the fixed pseudo-time `τ ∈ [0, T_f]`
/// (`T_f = pb.duration_s`, `pb.dt_s` its step) `dx/dτ = x9 · h(x8, x, u)`, `dx8/dτ = x9`,
/// `dx9/dτ = 0`, so the manoeuvre really lasts `x9 T_f`; the profile's knots are stretched to
/// `[0, x9 T_f]`. The outcome's cost gains `J_T = c_t · x9 · T_f` (4.10).
///
/// Errors: `scale` not finite and positive, and those of [`simulate`].
pub fn simulate_time_scaled(
    pb: &Problem,
    p: &[f64],
    scale: f64,
    c_t: f64,
) -> Result<Outcome, String> {
    if !(scale.is_finite() && scale > 0.0) {
        return Err(format!("time scale {scale}"));
    }
    let real = Problem {
        duration_s: scale * pb.duration_s,
        dt_s: scale * pb.dt_s,
        ..pb.clone()
    };
    let plan = real.profile(p)?;
    let (mut o, _) = run_scaled(&real, scale, |t, h| command(&real, &plan, t, h), 0, false)?;
    o.cost += c_t * scale * pb.duration_s;
    Ok(o)
}

/// Minimum-time planning (seed 001 eqs. 4.8–4.10): Nelder–Mead over the interior knots and the
/// time scale `x9 ∈ [scale_lo, scale_hi]` (started at 1, i.e. `pb.duration_s`), cost
/// [`simulate_time_scaled`]; `restarts` extra runs from the best point. Returns the knot
/// parameters, the scale (the manoeuvre lasts `scale · pb.duration_s`) and the outcome.
pub fn plan_minimum_time(
    pb: &Problem,
    c_t: f64,
    scale_lo: f64,
    scale_hi: f64,
    evals_per_run: usize,
    restarts: usize,
) -> Result<(Vec<f64>, f64, Outcome), String> {
    if !(scale_lo > 0.0 && scale_lo <= scale_hi && scale_hi.is_finite()) {
        return Err(format!("time scale bounds [{scale_lo}, {scale_hi}]"));
    }
    let n = pb.n_params();
    let mut x = pb.initial_guess();
    x.push(1.0f64.clamp(scale_lo, scale_hi));
    let lo: Vec<f64> = core::iter::repeat_n(-1.0, n).chain([scale_lo]).collect();
    let hi: Vec<f64> = core::iter::repeat_n(1.0, n).chain([scale_hi]).collect();
    let cost = |v: &[f64]| {
        simulate_time_scaled(pb, &v[..n], v[n], c_t)
            .map(|o| o.cost)
            .unwrap_or(f64::MAX)
    };
    for _ in 0..=restarts {
        x = nelder_mead_box(cost, &x, &lo, &hi, evals_per_run, 1e-18, 1e-12).x;
    }
    let scale = x[n];
    let o = simulate_time_scaled(pb, &x[..n], scale, c_t)?;
    x.truncate(n);
    Ok((x, scale, o))
}

/// The dipole profile of **direct dynamics** (note 001 §3.3, Fig. 4.1): per axis a clamped
/// spline (zero end slopes) through `n` ordinates (A·m²), clipped to ±`m_max`; `p` = all x
/// ordinates, then y, then z (`n = p.len()/3`, uniformly spaced knots), then, with
/// [`Problem::variable_grid`] (seed 001 Table 6.5, direct column), one gap parameter per
/// interior knot as in [`Problem::knot_times`] (`p.len() = 4n − 2`; `0.5` = uniform).
pub fn direct_profile(
    pb: &Problem,
    p: &[f64],
) -> Result<[crate::planning::spline::ClampedSpline<MAX_KNOTS>; 3], String> {
    let n = if pb.variable_grid {
        (p.len() + 2) / 4
    } else {
        p.len() / 3
    };
    let expected = if pb.variable_grid { 4 * n - 2 } else { 3 * n };
    if !(2..=MAX_KNOTS).contains(&n) || p.len() != expected {
        return Err(format!("{} direct-dynamics parameters", p.len()));
    }
    let times: Vec<f32> = if pb.variable_grid {
        pb.knot_times(&p[3 * n..])
            .into_iter()
            .map(|t| t as f32)
            .collect()
    } else {
        (0..n)
            .map(|k| (pb.duration_s * k as f64 / (n - 1) as f64) as f32)
            .collect()
    };
    let axis = |j: usize| {
        let v: Vec<f32> = p[j * n..(j + 1) * n].iter().map(|x| *x as f32).collect();
        crate::planning::spline::ClampedSpline::new(&times, &v, 0.0, 0.0).map_err(|e| e.to_string())
    };
    Ok([axis(0)?, axis(1)?, axis(2)?])
}

/// Simulates **direct dynamics** (magnetorquers only): the dipole of [`direct_profile`], cost
/// (6.3)/(6.5) with the third weight on `∫ mᵀm dt`.
pub fn simulate_direct(
    pb: &Problem,
    p: &[f64],
    record_every: usize,
) -> Result<(Outcome, Vec<Sample>), String> {
    let splines = direct_profile(pb, p)?;
    let (_, t_end) = splines[0].interval();
    let cmd = |t: f64, _h: &[f64; 3]| -> Result<Command, String> {
        let tt = (t as f32).min(t_end);
        let mut m = [0.0f64; 3];
        for (mj, sp) in m.iter_mut().zip(splines.iter()) {
            let v = sp.eval(tt).map_err(|e| e.to_string())?.value as f64;
            *mj = v.clamp(-pb.m_max_am2, pb.m_max_am2);
        }
        Ok(Command {
            dipole_am2: m,
            wheel_torque_nm: [0.0; 3],
            lost2: 0.0,
            q_plan: pb.q_start,
            omega_plan: [0.0; 3],
        })
    };
    run(pb, cmd, record_every, true)
}

fn run<C: Fn(f64, &[f64; 3]) -> Result<Command, String>>(
    pb: &Problem,
    command_at: C,
    record_every: usize,
    weight_on_dipole: bool,
) -> Result<(Outcome, Vec<Sample>), String> {
    run_scaled(pb, 1.0, command_at, record_every, weight_on_dipole)
}

/// [`run`] in seed 001's scaled time (eqs. 4.8–4.9): the pseudo-time `τ` runs over
/// `pb.duration_s / scale` in steps of `pb.dt_s / scale`; the real time is `x8 = scale · τ`
/// and every derivative is multiplied by `x9 = scale`. `scale = 1` is [`run`].
fn run_scaled<C: Fn(f64, &[f64; 3]) -> Result<Command, String>>(
    pb: &Problem,
    scale: f64,
    command_at: C,
    record_every: usize,
    weight_on_dipole: bool,
) -> Result<(Outcome, Vec<Sample>), String> {
    if !(scale.is_finite() && scale > 0.0) {
        return Err(format!("time scale {scale}"));
    }
    let q0 = pb.q_start;
    let mut x: State = [
        q0.q0 as f64,
        q0.q1 as f64,
        q0.q2 as f64,
        q0.q3 as f64,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ];
    let steps = (pb.duration_s / pb.dt_s).round().max(1.0) as usize;
    // pseudo-time step dτ; real time x8 = scale · τ
    let dt = pb.duration_s / scale / steps as f64;
    let mut lost = 0.0;
    let mut effort = 0.0;
    let mut max_m = 0.0f64;
    let mut max_ws = 0.0f64;
    let mut out = Vec::new();
    let hmax = pb.wheels.map(|w| w.inertia_kgm2 * w.max_speed_radps);
    let f = |tau: f64, x: &State| -> Result<(State, Command), String> {
        let t = scale * tau; // x8, the real time
        let h = [x[7], x[8], x[9]];
        let mut cmd = command_at(t, &h)?;
        if let Some(hm) = hmax {
            for i in 0..3 {
                if h[i].abs() >= hm && cmd.wheel_torque_nm[i] * h[i] > 0.0 {
                    cmd.wheel_torque_nm[i] = 0.0;
                }
            }
        }
        let q = [x[0], x[1], x[2], x[3]];
        let w = [x[4], x[5], x[6]];
        let b_t = pb.field_nt(t)?.map(|b| b * 1e-9);
        let b_body = to_body(q, b_t);
        let tau_m = cross(cmd.dipole_am2, b_body);
        let iw = [
            pb.inertia_kgm2[0] * w[0],
            pb.inertia_kgm2[1] * w[1],
            pb.inertia_kgm2[2] * w[2],
        ];
        let gyro = cross(w, [iw[0] + h[0], iw[1] + h[1], iw[2] + h[2]]);
        let qd = qmul(q, [0.0, w[0], w[1], w[2]]);
        let mut d = [0.0; 10];
        for i in 0..4 {
            d[i] = 0.5 * qd[i];
        }
        for i in 0..3 {
            d[4 + i] = (tau_m[i] - cmd.wheel_torque_nm[i] - gyro[i]) / pb.inertia_kgm2[i];
            d[7 + i] = cmd.wheel_torque_nm[i];
        }
        // eq. (4.9): every derivative times x9 (exactly 1 unscaled)
        if scale != 1.0 {
            for v in d.iter_mut() {
                *v *= scale;
            }
        }
        Ok((d, cmd))
    };
    for k in 0..steps {
        let t = k as f64 * dt;
        let (k1, c1) = f(t, &x)?;
        if record_every > 0 && k % record_every == 0 {
            out.push(sample_of(scale * t, &x, c1));
        }
        // rectangle rule on the step grid, in real time (dt_real = x9 dτ)
        lost += c1.lost2 * dt * scale;
        effort += c1.dipole_am2.iter().map(|m| m * m).sum::<f64>() * dt * scale;
        max_m = c1.dipole_am2.iter().fold(max_m, |a, m| a.max(m.abs()));
        let add = |x: &State, k: &State, s: f64| -> State {
            let mut y = *x;
            for i in 0..10 {
                y[i] += s * k[i];
            }
            y
        };
        let (k2, _) = f(t + 0.5 * dt, &add(&x, &k1, 0.5 * dt))?;
        let (k3, _) = f(t + 0.5 * dt, &add(&x, &k2, 0.5 * dt))?;
        let (k4, _) = f(t + dt, &add(&x, &k3, dt))?;
        for i in 0..10 {
            x[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        let n = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2] + x[3] * x[3]).sqrt();
        for v in x.iter_mut().take(4) {
            *v /= n;
        }
        if let Some(w) = pb.wheels {
            for v in &x[7..10] {
                max_ws = max_ws.max(v.abs() / w.inertia_kgm2);
            }
        }
    }
    let (_, c_end) = f(pb.duration_s / scale, &x)?;
    if record_every > 0 {
        out.push(sample_of(pb.duration_s, &x, c_end));
    }
    // error quaternion q_e = q_end* ⊗ q (tracking::attitude_error's convention)
    let qe = pb.q_end;
    let e = qmul(
        [qe.q0 as f64, -qe.q1 as f64, -qe.q2 as f64, -qe.q3 as f64],
        [x[0], x[1], x[2], x[3]],
    );
    let dq2 = e[1] * e[1] + e[2] * e[2] + e[3] * e[3];
    let dw2 = x[4] * x[4] + x[5] * x[5] + x[6] * x[6];
    let [cq, cw, ct] = pb.weights;
    let outcome = Outcome {
        attitude_error_deg: (2.0 * dq2.sqrt().atan2(e[0].abs())).to_degrees(),
        rate_error_degps: dw2.sqrt().to_degrees(),
        cost: cq * dq2 + cw * dw2 + ct * if weight_on_dipole { effort } else { lost },
        lost_integral: lost,
        max_dipole_am2: max_m,
        max_wheel_speed_radps: max_ws,
    };
    Ok((outcome, out))
}

fn sample_of(t: f64, x: &State, cmd: Command) -> Sample {
    Sample {
        t_s: t,
        q: [x[0], x[1], x[2], x[3]],
        omega: [x[4], x[5], x[6]],
        h_rw: [x[7], x[8], x[9]],
        cmd,
    }
}

/// Result of [`nelder_mead`].
#[derive(Clone, Debug)]
pub struct Minimum {
    /// Best point.
    pub x: Vec<f64>,
    /// Its value.
    pub f: f64,
    /// Function evaluations used.
    pub evals: usize,
}

/// Bounded Nelder–Mead (note 001 §3.7, Algorithm 1; reflection 1, expansion 2, contractions ½,
/// shrink ½; initial simplex as fminsearch: +5 % per coordinate, 0.00025 if zero; points clamped
/// to `[lo, hi]`; a start coordinate on a bound is stepped the other way). Stops after `max_evals` or when the simplex's value spread is below `ftol`
/// and its size below `xtol`.
pub fn nelder_mead<F: FnMut(&[f64]) -> f64>(
    f: F,
    x0: &[f64],
    lo: f64,
    hi: f64,
    max_evals: usize,
    ftol: f64,
    xtol: f64,
) -> Minimum {
    let n = x0.len();
    nelder_mead_box(f, x0, &vec![lo; n], &vec![hi; n], max_evals, ftol, xtol)
}

/// [`nelder_mead`] with a bound per coordinate (`lo[i] ≤ x[i] ≤ hi[i]`; `lo`, `hi` as long as
/// `x0`), e.g. dipole ordinates in ±`m_max` and grid parameters in ±1.
pub fn nelder_mead_box<F: FnMut(&[f64]) -> f64>(
    mut f: F,
    x0: &[f64],
    lo: &[f64],
    hi: &[f64],
    max_evals: usize,
    ftol: f64,
    xtol: f64,
) -> Minimum {
    let n = x0.len();
    let clamp = |x: Vec<f64>| -> Vec<f64> {
        x.into_iter()
            .enumerate()
            .map(|(i, v)| {
                let (l, h) = (lo.get(i).copied(), hi.get(i).copied());
                v.max(l.unwrap_or(f64::MIN)).min(h.unwrap_or(f64::MAX))
            })
            .collect()
    };
    let mut evals = 0usize;
    let mut simplex: Vec<(Vec<f64>, f64)> = Vec::with_capacity(n + 1);
    let mut eval = |x: &[f64], evals: &mut usize| -> f64 {
        *evals += 1;
        let v = f(x);
        if v.is_finite() {
            v
        } else {
            f64::MAX
        }
    };
    let v0 = eval(x0, &mut evals);
    simplex.push((x0.to_vec(), v0));
    for i in 0..n {
        let mut x = x0.to_vec();
        x[i] = if x[i] != 0.0 { 1.05 * x[i] } else { 0.00025 };
        let mut x = clamp(x);
        if x[i] == x0[i] {
            // the start is on a bound: step the other way (the simplex stays non-degenerate)
            x[i] = if x0[i] != 0.0 { 0.95 * x0[i] } else { -0.00025 };
            x = clamp(x);
        }
        let v = eval(&x, &mut evals);
        simplex.push((x, v));
    }
    while evals < max_evals {
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        let spread = simplex[n].1 - simplex[0].1;
        let size = simplex[1..]
            .iter()
            .flat_map(|(x, _)| x.iter().zip(&simplex[0].0).map(|(a, b)| (a - b).abs()))
            .fold(0.0f64, f64::max);
        if spread <= ftol && size <= xtol {
            break;
        }
        let centroid: Vec<f64> = (0..n)
            .map(|j| simplex[..n].iter().map(|(x, _)| x[j]).sum::<f64>() / n as f64)
            .collect();
        let worst = simplex[n].clone();
        let line = |t: f64| -> Vec<f64> {
            clamp(
                centroid
                    .iter()
                    .zip(&worst.0)
                    .map(|(c, w)| c + t * (w - c))
                    .collect(),
            )
        };
        let xr = line(-1.0);
        let fr = eval(&xr, &mut evals);
        if simplex[0].1 <= fr && fr < simplex[n - 1].1 {
            simplex[n] = (xr, fr);
        } else if fr < simplex[0].1 {
            let xe = line(-2.0);
            let fe = eval(&xe, &mut evals);
            simplex[n] = if fe < fr { (xe, fe) } else { (xr, fr) };
        } else {
            let accepted = if fr < worst.1 {
                let xc = line(-0.5);
                let fc = eval(&xc, &mut evals);
                (fc <= fr).then_some((xc, fc))
            } else {
                let xc = line(0.5);
                let fc = eval(&xc, &mut evals);
                (fc < worst.1).then_some((xc, fc))
            };
            match accepted {
                Some(p) => simplex[n] = p,
                None => {
                    let best = simplex[0].0.clone();
                    for (x, v) in simplex.iter_mut().skip(1) {
                        let xs = clamp(
                            best.iter()
                                .zip(x.iter())
                                .map(|(b, a)| 0.5 * (b + a))
                                .collect(),
                        );
                        *v = eval(&xs, &mut evals);
                        *x = xs;
                    }
                }
            }
        }
    }
    simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
    let (x, f) = simplex.swap_remove(0);
    Minimum { x, f, evals }
}

/// Bounded pattern (compass) search (note 001 §3.7, Algorithm 2): polls `x ± γ e_i` in turn,
/// moves to the first point with a simple decrease and doubles γ (`φ = 2`), else halves it
/// (`θ = ½`); stops when `γ ≤ gamma_tol` or after `max_evals`. Points clamped to `[lo, hi]`.
/// Defaults of MATLAB's `patternsearch` at the time (note 001, assumed): `γ0 = 1`, `γ_tol = 1e-6`.
#[allow(clippy::too_many_arguments)]
pub fn pattern_search<F: FnMut(&[f64]) -> f64>(
    mut f: F,
    x0: &[f64],
    lo: f64,
    hi: f64,
    gamma0: f64,
    gamma_tol: f64,
    max_evals: usize,
) -> Minimum {
    let mut x = x0.iter().map(|v| v.clamp(lo, hi)).collect::<Vec<_>>();
    let mut fx = f(&x);
    let mut evals = 1usize;
    let mut gamma = gamma0;
    while gamma > gamma_tol && evals < max_evals {
        let mut improved = false;
        'poll: for i in 0..x.len() {
            for sign in [1.0, -1.0] {
                let mut y = x.clone();
                y[i] = (y[i] + sign * gamma).clamp(lo, hi);
                if y[i] == x[i] {
                    continue;
                }
                let fy = f(&y);
                evals += 1;
                if fy < fx {
                    x = y;
                    fx = fy;
                    improved = true;
                    break 'poll;
                }
                if evals >= max_evals {
                    break 'poll;
                }
            }
        }
        gamma *= if improved { 2.0 } else { 0.5 };
    }
    Minimum { x, f: fx, evals }
}

/// Which derivative-free optimiser [`plan_with`] uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Optimiser {
    /// [`nelder_mead`], restarted from its best point.
    NelderMead,
    /// [`pattern_search`] (γ0 = 0.1, γ_tol = 1e-9), then the restarts with Nelder–Mead.
    PatternSearch,
}

/// Plans with the chosen optimiser; `evals_per_run` evaluations per run, `restarts` extra
/// Nelder–Mead runs from the best point.
pub fn plan_with(
    pb: &Problem,
    optimiser: Optimiser,
    evals_per_run: usize,
    restarts: usize,
) -> Result<(Vec<f64>, Outcome), String> {
    let mut x = pb.initial_guess();
    let cost = |p: &[f64]| simulate(pb, p, 0).map(|(o, _)| o.cost).unwrap_or(f64::MAX);
    let nm_runs = match optimiser {
        Optimiser::NelderMead => restarts + 1,
        Optimiser::PatternSearch => {
            x = pattern_search(cost, &x, -1.0, 1.0, 0.1, 1e-9, evals_per_run).x;
            restarts
        }
    };
    for _ in 0..nm_runs {
        x = nelder_mead(cost, &x, -1.0, 1.0, evals_per_run, 1e-18, 1e-12).x;
    }
    let (o, _) = simulate(pb, &x, 0)?;
    Ok((x, o))
}

/// Plans: Nelder–Mead from the straight-line guess, restarted from its best point `restarts`
/// times, each with `evals_per_run` evaluations. Returns the parameters and the outcome.
pub fn plan(
    pb: &Problem,
    evals_per_run: usize,
    restarts: usize,
) -> Result<(Vec<f64>, Outcome), String> {
    let mut x = pb.initial_guess();
    let cost = |p: &[f64]| simulate(pb, p, 0).map(|(o, _)| o.cost).unwrap_or(f64::MAX);
    for _ in 0..=restarts {
        let m = nelder_mead(cost, &x, -1.0, 1.0, evals_per_run, 1e-18, 1e-12);
        x = m.x;
    }
    let (o, _) = simulate(pb, &x, 0)?;
    Ok((x, o))
}
