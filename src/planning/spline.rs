//! Clamped cubic spline (seed 001 §4.2, eqs. 4.14–4.20; eqs. 4.18–4.19 are missing from the
//! thesis text and reconstructed in note 001 §3.6) and the attitude profile built from three of
//! them (eqs. 3.15–3.17).
//!
//! # Equations
//! Knots `t_k` (strictly increasing), values `y_k`, end slopes `v_1`, `v_n`; `T_k = t_{k+1} − t_k`.
//! Interior slopes from the tridiagonal system (4.19), solved by the Thomas algorithm (strictly
//! diagonally dominant, no pivoting needed):
//! ```text
//! T_{k+1} v_k + 2(T_k + T_{k+1}) v_{k+1} + T_k v_{k+2}
//!     = 3/(T_k T_{k+1}) · [T_k² (y_{k+2} − y_{k+1}) + T_{k+1}² (y_{k+1} − y_k)]
//! ```
//! then each segment `y = a0 + a1 τ + a2 τ² + a3 τ³`, `τ = t − t_k` (4.18):
//! `a0 = y_k`, `a1 = v_k`, `a2 = [3(y_{k+1} − y_k)/T_k − 2v_k − v_{k+1}]/T_k`,
//! `a3 = [2(y_k − y_{k+1})/T_k + v_k + v_{k+1}]/T_k²`.
//!
//! # Symbols
//! | name | thesis | unit |
//! |---|---|---|
//! | `knots_s` | `t_k` | s |
//! | `values` | `q_k` | any |
//! | `slope_start`, `slope_end` | `v_1`, `v_n` | value/s |
//!
//! Capacity `N` knots (fixed arrays, no allocation); `N ≤ 32` is the intended range.
//!
//! # Accuracy (measured, `cargo test --test planning -- --nocapture spline`)
//! A cubic over 1500 s on uneven knots is reproduced to f32 rounding: value 2.5e-8 absolute
//! (values ≈ 0.3), first derivative 4e-7 and second 1.4e-6 relative to their scale; the worked
//! example of note 001 §3.6 matches its 7 printed digits (1.8e-7 relative).

use crate::attitude::Quaternion;
use crate::linalg::Vec3;

use super::kinematics::{complete_from_vector_part, rates_of_jet, QuaternionJet};
use super::PlanningError;

/// A clamped cubic spline over at most `N` knots.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct ClampedSpline<const N: usize> {
    knots_s: [f32; N],
    /// Per segment `[a0, a1, a2, a3]`; the last row is unused.
    coef: [[f32; 4]; N],
    len: usize,
}

/// Value, first and second derivative at one time.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SplinePoint {
    /// `y(t)`.
    pub value: f32,
    /// `ẏ(t)`, per second.
    pub d1: f32,
    /// `ÿ(t)`, per second².
    pub d2: f32,
}

impl<const N: usize> ClampedSpline<N> {
    /// Builds the spline through `(knots_s[k], values[k])` with end slopes `slope_start`,
    /// `slope_end`. `knots_s` and `values` must have the same length, 2..=N, knots strictly
    /// increasing and everything finite.
    pub fn new(
        knots_s: &[f32],
        values: &[f32],
        slope_start: f32,
        slope_end: f32,
    ) -> Result<Self, PlanningError> {
        let n = knots_s.len();
        if n < 2 || n > N || values.len() != n {
            return Err(PlanningError::KnotCount(n));
        }
        if !knots_s
            .iter()
            .chain(values.iter())
            .chain([slope_start, slope_end].iter())
            .all(|x| x.is_finite())
        {
            return Err(PlanningError::NotFinite);
        }
        for (i, w) in knots_s.windows(2).enumerate() {
            if let [a, b] = w {
                if b - a <= 0.0 {
                    return Err(PlanningError::KnotsNotIncreasing(i + 1));
                }
            }
        }
        let mut knots = [0.0f32; N];
        for (d, s) in knots.iter_mut().zip(knots_s.iter()) {
            *d = *s;
        }
        // Full n×n tridiagonal system: rows 0 and n−1 are v = v_1, v = v_n; Thomas forward sweep
        // stores c' (modified super-diagonal) and d' (modified right-hand side).
        let mut c_mod = [0.0f32; N];
        let mut d_mod = [0.0f32; N];
        let mut v = [0.0f32; N];
        if let (Some(c0), Some(d0)) = (c_mod.first_mut(), d_mod.first_mut()) {
            *c0 = 0.0;
            *d0 = slope_start;
        }
        for i in 1..n {
            let (sub, diag, sup, rhs) = if i + 1 == n {
                (0.0, 1.0, 0.0, slope_end)
            } else {
                let (t0, t1, t2) = (at(knots_s, i - 1)?, at(knots_s, i)?, at(knots_s, i + 1)?);
                let (y0, y1, y2) = (at(values, i - 1)?, at(values, i)?, at(values, i + 1)?);
                let (h0, h1) = (t1 - t0, t2 - t1);
                let rhs = 3.0 / (h0 * h1) * (h0 * h0 * (y2 - y1) + h1 * h1 * (y1 - y0));
                (h1, 2.0 * (h0 + h1), h0, rhs)
            };
            let c_prev = at(&c_mod, i - 1)?;
            let d_prev = at(&d_mod, i - 1)?;
            let denom = diag - sub * c_prev;
            set(&mut c_mod, i, sup / denom)?;
            set(&mut d_mod, i, (rhs - sub * d_prev) / denom)?;
        }
        // back substitution
        let mut next = 0.0f32;
        for i in (0..n).rev() {
            let vi = if i + 1 == n {
                at(&d_mod, i)?
            } else {
                at(&d_mod, i)? - at(&c_mod, i)? * next
            };
            set(&mut v, i, vi)?;
            next = vi;
        }
        let mut coef = [[0.0f32; 4]; N];
        for k in 0..n - 1 {
            let h = at(knots_s, k + 1)? - at(knots_s, k)?;
            let (y0, y1) = (at(values, k)?, at(values, k + 1)?);
            let (v0, v1) = (at(&v, k)?, at(&v, k + 1)?);
            let row = coef.get_mut(k).ok_or(PlanningError::KnotCount(n))?;
            *row = [
                y0,
                v0,
                (3.0 * (y1 - y0) / h - 2.0 * v0 - v1) / h,
                (2.0 * (y0 - y1) / h + v0 + v1) / (h * h),
            ];
        }
        Ok(Self {
            knots_s: knots,
            coef,
            len: n,
        })
    }

    /// Number of knots.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Always false (a spline has at least two knots); for clippy's `len_without_is_empty`.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// First and last knot times, s.
    pub fn interval(&self) -> (f32, f32) {
        let first = self.knots_s.first().copied().unwrap_or(0.0);
        let last = self
            .knots_s
            .get(self.len.saturating_sub(1))
            .copied()
            .unwrap_or(first);
        (first, last)
    }

    /// Coefficients `[a0, a1, a2, a3]` of segment `k` (0-based, local time `τ = t − t_k`).
    pub fn segment(&self, k: usize) -> Option<[f32; 4]> {
        if k + 1 < self.len {
            self.coef.get(k).copied()
        } else {
            None
        }
    }

    /// Value, first and second derivative at `t_s` (inside the knot interval, ends included).
    pub fn eval(&self, t_s: f32) -> Result<SplinePoint, PlanningError> {
        let (t0, t1) = self.interval();
        if !t_s.is_finite() || t_s < t0 || t_s > t1 {
            return Err(PlanningError::OutOfRange(t_s));
        }
        // last segment whose start is ≤ t (bounded scan over N)
        let mut k = 0usize;
        for (i, tk) in self
            .knots_s
            .iter()
            .enumerate()
            .take(self.len.saturating_sub(1))
        {
            if *tk <= t_s {
                k = i;
            }
        }
        let tk = self.knots_s.get(k).copied().unwrap_or(t0);
        let [a0, a1, a2, a3] = self.coef.get(k).copied().unwrap_or([0.0; 4]);
        let tau = t_s - tk;
        Ok(SplinePoint {
            value: a0 + tau * (a1 + tau * (a2 + tau * a3)),
            d1: a1 + tau * (2.0 * a2 + 3.0 * a3 * tau),
            d2: 2.0 * a2 + 6.0 * a3 * tau,
        })
    }
}

fn at(a: &[f32], i: usize) -> Result<f32, PlanningError> {
    a.get(i).copied().ok_or(PlanningError::KnotCount(i))
}

fn set(a: &mut [f32], i: usize, x: f32) -> Result<(), PlanningError> {
    let slot = a.get_mut(i).ok_or(PlanningError::KnotCount(i))?;
    *slot = x;
    Ok(())
}

/// The attitude, rate and acceleration at one time of an [`AttitudeSpline`].
#[derive(Copy, Clone, Debug, PartialEq)]
// no defmt::Format: nalgebra's Vec3 does not implement it
pub struct AttitudeSample {
    /// Quaternion and derivatives ([`crate::attitude`] convention).
    pub jet: QuaternionJet,
    /// Body rate ω, rad/s, body axes.
    pub omega_radps: Vec3,
    /// Body acceleration ω̇, rad/s², body axes.
    pub omega_dot_radps2: Vec3,
}

/// An attitude profile as seed 001's inverse dynamics (eqs. 3.15–3.17): the vector part
/// `q1, q2, q3` of the scalar-first quaternion ([`crate::attitude`]) splined over the same knots,
/// `q0 = +√(1 − |q_v|²)`.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct AttitudeSpline<const N: usize> {
    axes: [ClampedSpline<N>; 3],
}

impl<const N: usize> AttitudeSpline<N> {
    /// Builds the profile through the attitudes `q_knots` (scalar-first, each with `q0 > 0`;
    /// use [`Quaternion::canonical`]) at `knots_s`, with the end body rates `omega_start_radps`,
    /// `omega_end_radps` (rad/s, body axes; zero for rest-to-rest), which give the clamped
    /// end slopes of the vector part `q̇_v = ½ (q0 ω + q_v × ω)`.
    pub fn new(
        knots_s: &[f32],
        q_knots: &[Quaternion],
        omega_start_radps: &Vec3,
        omega_end_radps: &Vec3,
    ) -> Result<Self, PlanningError> {
        let n = knots_s.len();
        if n < 2 || n > N || q_knots.len() != n {
            return Err(PlanningError::KnotCount(n));
        }
        let (Some(q_first), Some(q_last)) = (q_knots.first(), q_knots.last()) else {
            return Err(PlanningError::KnotCount(n));
        };
        let s0 = super::kinematics::quaternion_rate(q_first, omega_start_radps);
        let s1 = super::kinematics::quaternion_rate(q_last, omega_end_radps);
        let mut comp = [[0.0f32; N]; 3];
        for (k, q) in q_knots.iter().enumerate() {
            if q.q0.is_nan() || q.q0 <= 0.0 {
                return Err(PlanningError::VectorPartTooLong(1.0));
            }
            for (c, x) in comp.iter_mut().zip([q.q1, q.q2, q.q3]) {
                set(c, k, x)?;
            }
        }
        let [c1, c2, c3] = &comp;
        Ok(Self {
            axes: [
                ClampedSpline::new(knots_s, c1.get(..n).unwrap_or(&[]), s0.q1, s1.q1)?,
                ClampedSpline::new(knots_s, c2.get(..n).unwrap_or(&[]), s0.q2, s1.q2)?,
                ClampedSpline::new(knots_s, c3.get(..n).unwrap_or(&[]), s0.q3, s1.q3)?,
            ],
        })
    }

    /// First and last knot times, s.
    pub fn interval(&self) -> (f32, f32) {
        let [a, _, _] = &self.axes;
        a.interval()
    }

    /// The component splines of `q1, q2, q3`.
    pub fn axes(&self) -> &[ClampedSpline<N>; 3] {
        &self.axes
    }

    /// Attitude, body rate and acceleration at `t_s` (note 001 §1.5 inverse kinematics).
    pub fn sample(&self, t_s: f32) -> Result<AttitudeSample, PlanningError> {
        let [a, b, c] = &self.axes;
        let (pa, pb, pc) = (a.eval(t_s)?, b.eval(t_s)?, c.eval(t_s)?);
        let jet = complete_from_vector_part(
            &Vec3::new(pa.value, pb.value, pc.value),
            &Vec3::new(pa.d1, pb.d1, pc.d1),
            &Vec3::new(pa.d2, pb.d2, pc.d2),
        )?;
        let (omega_radps, omega_dot_radps2) = rates_of_jet(&jet)?;
        Ok(AttitudeSample {
            jet,
            omega_radps,
            omega_dot_radps2,
        })
    }
}
