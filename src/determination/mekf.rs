//! The flight attitude estimator: a multiplicative extended Kalman filter (MEKF) with gyro-bias
//! and magnetometer-bias states (Lefferts, Markley and Shuster 1982; Markley and Crassidis,
//! *Fundamentals of Spacecraft Attitude Determination and Control*, 2014, §6.2.4, Table 6.3).
//!
//! Attitudes follow [`crate::attitude`]: `v_body = A(q) · v_ref`, reference TEME of date,
//! quaternions scalar-first, `A(p ⊗ r) = A(r) · A(p)`.
//!
//! # State
//! The estimate is the quaternion `q̂`, the gyro bias `β̂` (rad/s, body) and the magnetometer
//! bias `m̂` (nT, body: what the fused field of [`super::least_squares`] reads with no field,
//! the spacecraft's residual dipole at the magnetometers and their offsets). The filter's
//! covariance `P` is that of the 9 error states `x = (δθ, δβ, δm)`, with the attitude error a
//! small rotation in body axes: `q = q̂ ⊗ (1, δθ/2)`, `A(q) = (I − [δθ×]) A(q̂)`.
//!
//! # Propagation (eq. 6.60, first order)
//! With the gyros' rate `ω` (the mean over the period, [`super::least_squares`]) and
//! `ω̂ = ω − β̂`: `q̂ ← q̂ ⊗ (1, ω̂Δt/2)`, renormalised; `P ← Φ P Φᵀ + Q` with
//! `Φ = I + F Δt`, `F = [[−[ω̂×], −I, 0], [0, 0, 0], [0, 0, 0]]`, and `Q` diagonal:
//! `σ_v² Δt + σ_u² Δt³/3` (attitude), `σ_u² Δt` (gyro bias), `σ_m² Δt` (magnetometer bias)
//! ([`MekfConfig`]; the attitude–bias cross term `−σ_u² Δt²/2` is left out: 4e-15 rad²
//! against the 6e-8 rad² of the diagonal at the flight's figures). `Φ` touches only the
//! attitude rows, so `Φ P Φᵀ` is two passes of the same 3-vector operation over the attitude
//! rows and columns, not a 9 × 9 product.
//!
//! # Measurement update (sequential scalar updates, no matrix inverse)
//! A vector observation `y = A v_ref` (+ `m` for the field) gives `y − ŷ = [ŷ×] δθ (+ δm)`,
//! `ŷ = A(q̂) v_ref` (eq. 6.41): three scalar measurements, row `k` of `H` being row `k` of
//! `[ŷ×]` (and `e_k` on the magnetometer bias). Each is processed in turn with the
//! linearisation of the step (the innovation less `H δx`, the correction accumulated so far),
//! and the correction is applied once at the end: `q̂ ← q̂ ⊗ (1, δθ/2)`, renormalised,
//! `β̂ += δβ`, `m̂ += δm`. For one scalar, with `u = P hᵀ`, `S = h u + R`, `K = u / S`:
//!
//! **Joseph form** `P ← (I − K h) P (I − K h)ᵀ + K R Kᵀ = P − K uᵀ − u Kᵀ + S K Kᵀ`,
//! evaluated as `P + K wᵀ − u Kᵀ` with `w = S K − u` (zero but for the rounding of `K`) on the
//! packed upper triangle, so `P` is symmetric by construction and the update stays first-order
//! insensitive to the error of the computed gain (Bucy and Joseph 1968). A step that leaves a
//! diagonal element not positive or any element not finite drops the estimate (reported as
//! no attitude; the next two-vector solution restarts it). `tests/mekf.rs` runs 10 million
//! steps and checks symmetry (by construction), positive diagonals and every 3 × 3 block's
//! positive determinant along the way.
//!
//! # Measurement noise
//! - **Sun** (one unit vector): `σ² = σ_floor² + σ₀² / n² Σᵢ 1/cos²θᵢ` over the `n` lit
//!   sensors averaged ([`sun_variance_rad2`]): each sensor's noise grows as `1/cos θ` of its
//!   incidence (a centroid's noise grows as its signal falls); the floor is its calibration
//!   residual and alignment, which do not average.
//! - **Field**: `σ² = σ_abs² + (k |B_ref|)²` per axis: the magnetometers' noise and
//!   quantisation, and the part that scales with the field (scale factors, misalignment, the
//!   field model's error). The unit vector's `R = σ² I` is the measurement model of Shuster
//!   (1989), exact for the rows of `[ŷ×]`.
//!
//! # Innovation gate
//! A scalar with `ν² > γ S` (`ν` its innovation, [`MekfConfig::gate_chi2`] = `γ`, a χ² with one
//! degree of freedom) is refused and counted; it also serves fault detection: a sensor whose
//! every measurement is refused for [`MekfConfig::refused_steps_to_restart`] steps in a row
//! restarts the filter from the two-vector solution (the estimate had diverged, or the sensor
//! has).
//!
//! # Use
//! [`Mekf::start`] from a two-vector (Wahba) solution, then each step [`Mekf::propagate`],
//! [`Mekf::update_sun`] and [`Mekf::update_field`] as measurements come, and
//! [`Mekf::attitude_sigma_rad`] decides whether the estimate is still usable
//! ([`MekfConfig::max_attitude_sigma_rad`]).
//!
//! **Accuracy** (f32): `cargo test --test mekf -- --nocapture` runs the filter in f32 beside
//! the same equations in f64 on one simulated hour; the estimates differ by at most the bound
//! stated in [`F32_ATTITUDE_BOUND_RAD`].

use crate::attitude::Quaternion;
use crate::fmath;
use crate::linalg::{cross, dot, finite3, mat_vec, Vec3};

/// Error states: attitude (3), gyro bias (3), magnetometer bias (3).
pub const STATES: usize = 9;
/// Entries of the packed upper triangle of `P`.
const PACKED: usize = STATES * (STATES + 1) / 2;
/// First index of the gyro-bias states.
const GYRO_BIAS: usize = 3;
/// First index of the magnetometer-bias states.
const MAG_BIAS: usize = 6;

/// The largest difference between this f32 filter's attitude and the same equations in f64
/// over one simulated hour of `tests/mekf.rs`, rad (measured 2.9e-6 rad; the bound 1e-5).
pub const F32_ATTITUDE_BOUND_RAD: f32 = 1.0e-5;

/// Index of `P(i, j)` in the packed upper triangle, row by row.
const fn packed(i: usize, j: usize) -> usize {
    let (i, j) = if i <= j { (i, j) } else { (j, i) };
    i * (2 * STATES + 1 - i) / 2 + (j - i)
}

/// The filter's tuning (see the [module docs](self) for where each enters).
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MekfConfig {
    /// `σ_v`: the gyros' angle random walk, rad/√s.
    pub gyro_arw_rad_per_sqrt_s: f32,
    /// `σ_u`: the gyro bias's random walk, rad/s/√s.
    pub gyro_bias_walk: f32,
    /// `σ_m`: the magnetometer bias's random walk, nT/√s.
    pub mag_bias_walk_nt_per_sqrt_s: f32,
    /// `σ₀`: a Sun sensor's noise at normal incidence, rad (1σ per axis).
    pub sun_noise_rad: f32,
    /// `σ_floor`: a Sun sensor's calibration residual and alignment, rad (1σ per axis).
    pub sun_floor_rad: f32,
    /// `σ_abs`: the fused field's noise, nT (1σ per axis).
    pub field_noise_nt: f32,
    /// `k`: the fused field's error proportional to the field, fraction (1σ per axis).
    pub field_relative: f32,
    /// Initial 1σ of the attitude, rad.
    pub initial_attitude_rad: f32,
    /// Initial 1σ of the gyro bias, rad/s.
    pub initial_gyro_bias_radps: f32,
    /// Initial 1σ of the magnetometer bias, nT.
    pub initial_mag_bias_nt: f32,
    /// `γ`: the innovation gate, `ν² ≤ γ S` (χ², one degree of freedom).
    pub gate_chi2: f32,
    /// Steps in a row with a sensor's every measurement refused before the filter restarts.
    pub refused_steps_to_restart: u8,
    /// The estimate is usable while the largest attitude 1σ is at most this, rad.
    pub max_attitude_sigma_rad: f32,
}

/// What one update did.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct UpdateOutcome {
    /// Scalar measurements taken.
    pub accepted: u8,
    /// Scalar measurements refused by the gate.
    pub refused: u8,
}

/// The filter's state: the estimate and its error covariance (see the [module docs](self)).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Mekf {
    /// The attitude, reference TEME → body, unit, scalar-first.
    pub attitude: Quaternion,
    /// The gyro bias, body, rad/s (subtracted from the gyros' rate).
    pub gyro_bias_radps: Vec3,
    /// The magnetometer bias, body, nT (subtracted from the fused field).
    pub mag_bias_nt: Vec3,
    /// The packed upper triangle of the error covariance, row by row.
    p: [f32; PACKED],
    /// Steps in a row with every Sun scalar refused, and with every field scalar refused.
    sun_refused_steps: u8,
    field_refused_steps: u8,
}

/// The Sun observation's variance, rad² per axis, from the lit sensors' incidence cosines
/// (`Σ 1/cos²θᵢ` over the `n` averaged, given as `inv_cos2_sum` and `n`; see the [module
/// docs](self)).
pub fn sun_variance_rad2(config: &MekfConfig, inv_cos2_sum: f32, n: u8) -> f32 {
    let n = f32::from(n.max(1));
    let s0 = config.sun_noise_rad;
    let floor = config.sun_floor_rad;
    floor * floor + s0 * s0 * inv_cos2_sum / (n * n)
}

impl Mekf {
    /// A filter at `attitude` (a two-vector solution) with the configured initial 1σ, the
    /// biases zero.
    pub fn start(config: &MekfConfig, attitude: Quaternion) -> Self {
        let mut filter = Self {
            attitude,
            gyro_bias_radps: Vec3::zeros(),
            mag_bias_nt: Vec3::zeros(),
            p: [0.0; PACKED],
            sun_refused_steps: 0,
            field_refused_steps: 0,
        };
        let a = config.initial_attitude_rad;
        let b = config.initial_gyro_bias_radps;
        let m = config.initial_mag_bias_nt;
        for i in 0..STATES {
            let s = match i {
                0..GYRO_BIAS => a,
                GYRO_BIAS..MAG_BIAS => b,
                _ => m,
            };
            filter.set(i, i, s * s);
        }
        filter
    }

    /// `P(i, j)` (0 outside the state, which no caller asks).
    fn at(&self, i: usize, j: usize) -> f32 {
        self.p.get(packed(i, j)).copied().unwrap_or(0.0)
    }

    fn set(&mut self, i: usize, j: usize, value: f32) {
        if let Some(e) = self.p.get_mut(packed(i, j)) {
            *e = value;
        }
    }

    /// The 1σ of each attitude error axis (body), rad: `√P(k, k)`.
    pub fn attitude_sigma_rad(&self) -> Vec3 {
        Vec3::new(
            fmath::sqrt(self.at(0, 0)),
            fmath::sqrt(self.at(1, 1)),
            fmath::sqrt(self.at(2, 2)),
        )
    }

    /// The covariance's diagonal: attitude (rad²), gyro bias (rad²/s²), magnetometer bias
    /// (nT²).
    pub fn variances(&self) -> [f32; STATES] {
        let mut d = [0.0; STATES];
        for (i, v) in d.iter_mut().enumerate() {
            *v = self.at(i, i);
        }
        d
    }

    /// The full covariance, for tests and the ground (`P(i, j)`).
    pub fn covariance(&self) -> [[f32; STATES]; STATES] {
        let mut m = [[0.0; STATES]; STATES];
        for (i, row) in m.iter_mut().enumerate() {
            for (j, e) in row.iter_mut().enumerate() {
                *e = self.at(i, j);
            }
        }
        m
    }

    /// True while the estimate is usable: every element finite, the diagonal positive and the
    /// attitude's largest 1σ within [`MekfConfig::max_attitude_sigma_rad`].
    pub fn is_usable(&self, config: &MekfConfig) -> bool {
        let limit = config.max_attitude_sigma_rad;
        let healthy = self.p.iter().all(|v| v.is_finite())
            && (0..STATES).all(|i| self.at(i, i) > 0.0)
            && finite3(&self.gyro_bias_radps)
            && finite3(&self.mag_bias_nt);
        healthy && (0..GYRO_BIAS).all(|i| limit * limit >= self.at(i, i))
    }

    /// The gyros' rate less the estimated bias, rad/s (body).
    pub fn rate_body_radps(&self, omega_body_radps: &Vec3) -> Vec3 {
        omega_body_radps - self.gyro_bias_radps
    }

    /// The bias estimates of the magnetometers (`mag`) or the gyros (`!mag`) no longer apply
    /// (the set of tiles read changed): their covariance goes back to the initial 1σ and
    /// loses its correlations, so the next measurements move the bias, not the attitude.
    pub fn forget_bias(&mut self, config: &MekfConfig, mag: bool) {
        let (first, sigma) = if mag {
            (MAG_BIAS, config.initial_mag_bias_nt)
        } else {
            (GYRO_BIAS, config.initial_gyro_bias_radps)
        };
        for i in first..first + 3 {
            for j in 0..STATES {
                self.set(i, j, 0.0);
            }
            self.set(i, i, sigma * sigma);
        }
    }

    /// Propagation over `dt_s` with the gyros' rate (see the [module docs](self)); `None` if
    /// the result is not usable (a non-finite rate or state).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    pub fn propagate(
        mut self,
        config: &MekfConfig,
        omega_body_radps: &Vec3,
        dt_s: f32,
    ) -> Option<Self> {
        let w = self.rate_body_radps(omega_body_radps);
        let half = w * (0.5 * dt_s);
        let dq = Quaternion {
            q0: 1.0,
            q1: half.x,
            q2: half.y,
            q3: half.z,
        };
        let q = self.attitude.mul(&dq);
        self.attitude = Quaternion::new_normalize(q.q0, q.q1, q.q2, q.q3)?;
        // Φ P: the attitude rows become x − (ω̂Δt) × x − Δt·(gyro-bias rows), column by column
        let w_dt = w * dt_s;
        let mut rows = [[0.0f32; STATES]; 3];
        let [r0, r1, r2] = &mut rows;
        for (j, ((e0, e1), e2)) in r0
            .iter_mut()
            .zip(r1.iter_mut())
            .zip(r2.iter_mut())
            .enumerate()
        {
            let x = Vec3::new(self.at(0, j), self.at(1, j), self.at(2, j));
            let b = Vec3::new(self.at(3, j), self.at(4, j), self.at(5, j));
            let y = phi(&x, &b, &w_dt, dt_s);
            (*e0, *e1, *e2) = (y.x, y.y, y.z);
        }
        // (Φ P) Φᵀ: the same on the attitude columns; rows beyond the attitude's are P's own
        for (i, row) in rows.iter().enumerate() {
            for (j, e) in row.iter().enumerate().skip(GYRO_BIAS) {
                self.set(i, j, *e);
            }
            let x = Vec3::new(row[0], row[1], row[2]);
            let b = Vec3::new(row[3], row[4], row[5]);
            let y = phi(&x, &b, &w_dt, dt_s);
            for (j, e) in [y.x, y.y, y.z].iter().enumerate().skip(i) {
                self.set(i, j, *e);
            }
        }
        let (v, u, m) = (
            config.gyro_arw_rad_per_sqrt_s,
            config.gyro_bias_walk,
            config.mag_bias_walk_nt_per_sqrt_s,
        );
        let q_att = v * v * dt_s + u * u * dt_s * dt_s * dt_s / 3.0;
        for i in 0..STATES {
            let add = match i {
                0..GYRO_BIAS => q_att,
                GYRO_BIAS..MAG_BIAS => u * u * dt_s,
                _ => m * m * dt_s,
            };
            self.set(i, i, self.at(i, i) + add);
        }
        self.is_usable(config).then_some(self)
    }

    /// The Sun's update: `sun_body` (unit, the sensors'), `sun_teme` (unit, the model's) and
    /// the observation's variance per axis ([`sun_variance_rad2`]).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    pub fn update_sun(
        &mut self,
        config: &MekfConfig,
        sun_body: &Vec3,
        sun_teme: &Vec3,
        variance_rad2: f32,
    ) -> UpdateOutcome {
        let predicted = mat_vec(self.attitude.to_dcm().matrix(), sun_teme);
        let outcome = self.update_vector(config, sun_body, &predicted, variance_rad2, false);
        self.sun_refused_steps = count_refused(self.sun_refused_steps, &outcome);
        outcome
    }

    /// The field's update: `b_body_nt` (the magnetometers' fused field) and `b_teme_nt` (the
    /// model's), with the magnetometer bias.
    #[cfg_attr(target_arch = "msp430", inline(never))]
    pub fn update_field(
        &mut self,
        config: &MekfConfig,
        b_body_nt: &Vec3,
        b_teme_nt: &Vec3,
    ) -> UpdateOutcome {
        let predicted = mat_vec(self.attitude.to_dcm().matrix(), b_teme_nt);
        let k = config.field_relative;
        let s = config.field_noise_nt;
        let variance = s * s + k * k * dot(b_teme_nt, b_teme_nt);
        let outcome = self.update_vector(config, b_body_nt, &predicted, variance, true);
        self.field_refused_steps = count_refused(self.field_refused_steps, &outcome);
        outcome
    }

    /// True when a sensor's every measurement has been refused for
    /// [`MekfConfig::refused_steps_to_restart`] steps in a row.
    pub fn diverged(&self, config: &MekfConfig) -> bool {
        let n = config.refused_steps_to_restart;
        self.sun_refused_steps >= n || self.field_refused_steps >= n
    }

    /// Three scalar updates with `y` against `ŷ` (+ the magnetometer bias if `mag`), then
    /// the correction applied.
    fn update_vector(
        &mut self,
        config: &MekfConfig,
        measured: &Vec3,
        predicted: &Vec3,
        variance: f32,
        mag: bool,
    ) -> UpdateOutcome {
        let mut dx = [0.0f32; STATES];
        let mut outcome = UpdateOutcome::default();
        let bias = if mag { self.mag_bias_nt } else { Vec3::zeros() };
        let p = predicted;
        // rows of [ŷ×]
        let rows = [
            Vec3::new(0.0, -p.z, p.y),
            Vec3::new(p.z, 0.0, -p.x),
            Vec3::new(-p.y, p.x, 0.0),
        ];
        let residuals = [
            measured.x - p.x - bias.x,
            measured.y - p.y - bias.y,
            measured.z - p.z - bias.z,
        ];
        for (k, (h, residual)) in rows.iter().zip(residuals).enumerate() {
            let b = mag.then_some(MAG_BIAS + k);
            if self.scalar_update(config, &mut dx, h, b, residual, variance) {
                outcome.accepted += 1;
            } else {
                outcome.refused += 1;
            }
        }
        self.apply(&dx);
        outcome
    }

    /// One scalar measurement `residual = h δθ (+ δm_b) + noise` of variance `r`: gated, then
    /// the Joseph-form update of `P` and the correction accumulated in `dx`. False if refused.
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn scalar_update(
        &mut self,
        config: &MekfConfig,
        dx: &mut [f32; STATES],
        h: &Vec3,
        bias: Option<usize>,
        residual: f32,
        r: f32,
    ) -> bool {
        let mut u = [0.0f32; STATES];
        for (i, ui) in u.iter_mut().enumerate() {
            let x = Vec3::new(self.at(i, 0), self.at(i, 1), self.at(i, 2));
            *ui = dot(&x, h) + bias.map_or(0.0, |b| self.at(i, b));
        }
        let at = |v: &[f32; STATES], b: Option<usize>| b.and_then(|b| v.get(b)).copied();
        let hu = h.x * u[0] + h.y * u[1] + h.z * u[2] + at(&u, bias).unwrap_or(0.0);
        let hdx = h.x * dx[0] + h.y * dx[1] + h.z * dx[2] + at(dx, bias).unwrap_or(0.0);
        let s = hu + r;
        let nu = residual - hdx;
        if !(s > 0.0) || !(config.gate_chi2 * s >= nu * nu) {
            return false;
        }
        let mut k = [0.0f32; STATES];
        for ((ki, ui), di) in k.iter_mut().zip(u.iter()).zip(dx.iter_mut()) {
            *ki = ui / s;
            *di += *ki * nu;
        }
        // Joseph form: P + K wᵀ − u Kᵀ, w = S K − u, on the upper triangle
        let mut w = [0.0f32; STATES];
        for ((wi, ki), ui) in w.iter_mut().zip(k.iter()).zip(u.iter()) {
            *wi = s * ki - ui;
        }
        let mut e = self.p.iter_mut();
        for (i, (ki, ui)) in k.iter().zip(u.iter()).enumerate() {
            for (kj, wj) in k.iter().zip(w.iter()).skip(i) {
                if let Some(e) = e.next() {
                    *e += ki * wj - ui * kj;
                }
            }
        }
        true
    }

    /// The accumulated correction applied to the estimate (the reset of the error state).
    fn apply(&mut self, dx: &[f32; STATES]) {
        let dq = Quaternion {
            q0: 1.0,
            q1: 0.5 * dx[0],
            q2: 0.5 * dx[1],
            q3: 0.5 * dx[2],
        };
        let q = self.attitude.mul(&dq);
        if let Some(q) = Quaternion::new_normalize(q.q0, q.q1, q.q2, q.q3) {
            self.attitude = q;
        }
        self.gyro_bias_radps += Vec3::new(dx[3], dx[4], dx[5]);
        self.mag_bias_nt += Vec3::new(dx[6], dx[7], dx[8]);
    }
}

/// `x − a × x − Δt·b`: one column (or row) of `Φ P` on the attitude states, with `a = ω̂Δt`.
#[cfg_attr(target_arch = "msp430", inline(never))]
fn phi(x: &Vec3, b: &Vec3, a: &Vec3, dt_s: f32) -> Vec3 {
    let c = cross(a, x);
    Vec3::new(
        x.x - c.x - dt_s * b.x,
        x.y - c.y - dt_s * b.y,
        x.z - c.z - dt_s * b.z,
    )
}

/// Steps in a row with every scalar of a sensor refused (a step with one taken resets it).
fn count_refused(steps: u8, outcome: &UpdateOutcome) -> u8 {
    if outcome.accepted == 0 && outcome.refused > 0 {
        steps.saturating_add(1)
    } else {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packed_indices_cover_the_triangle_once() {
        let mut seen = [false; PACKED];
        for i in 0..STATES {
            for j in i..STATES {
                let k = packed(i, j);
                assert!(!seen[k], "({i}, {j})");
                seen[k] = true;
                assert_eq!(packed(j, i), k);
            }
        }
        assert!(seen.iter().all(|s| *s));
        // row by row, as the Joseph update walks it
        let mut n = 0;
        for i in 0..STATES {
            for j in i..STATES {
                assert_eq!(packed(i, j), n);
                n += 1;
            }
        }
    }
}
