//! The flight attitude estimator: a multiplicative extended Kalman filter (MEKF) with gyro-bias,
//! magnetometer-bias and albedo states (Lefferts, Markley and Shuster 1982; Markley and Crassidis,
//! *Fundamentals of Spacecraft Attitude Determination and Control*, 2014, §6.2.4, Table 6.3).
//!
//! Attitudes follow [`crate::attitude`]: `v_body = A(q) · v_ref`, reference TEME of date,
//! quaternions scalar-first, `A(p ⊗ r) = A(r) · A(p)`.
//!
//! # State
//! The estimate is the quaternion `q̂`, the gyro bias `β̂` (rad/s, body) and the magnetometer
//! bias `m̂` (nT, body: what the fused field of [`super::least_squares`] reads with no field,
//! the spacecraft's residual dipole at the magnetometers and their offsets) and the Earth's
//! albedo `â` the Sun sensors see ([`crate::env::albedo`]; 0 ..= 1). The filter's covariance
//! `P` is that of the 10 error states `x = (δθ, δβ, δm, δa)`, with the attitude error a small
//! rotation in body axes: `q = q̂ ⊗ (1, δθ/2)`, `A(q) = (I − [δθ×]) A(q̂)`.
//!
//! # Propagation (eq. 6.60, first order)
//! With the gyros' rate `ω` (the mean over the period, [`super::least_squares`]) and
//! `ω̂ = ω − β̂`: `q̂ ← q̂ ⊗ (1, ω̂Δt/2)`, renormalised; `P ← Φ P Φᵀ + Q` with
//! `Φ = I + F Δt`, `F = [[−[ω̂×], −I, 0], [0, 0, 0], [0, 0, 0]]`, and `Q` diagonal:
//! `σ_v² Δt + σ_u² Δt³/3` (attitude), `σ_u² Δt` (gyro bias), `σ_m² Δt` (magnetometer bias),
//! `σ_a² Δt` (albedo) ([`MekfConfig`]; the attitude–bias cross term `−σ_u² Δt²/2` is left out: 4e-15 rad²
//! against the 6e-8 rad² of the diagonal at the flight's figures). `Φ` touches only the
//! attitude rows, so `Φ P Φᵀ` is two passes of the same 3-vector operation over the attitude
//! rows and columns, not a 10 × 10 product.
//!
//! # Measurement update (sequential scalar updates, no matrix inverse)
//! A vector observation `y = A v_ref` (+ `m` for the field) gives `y − ŷ = [ŷ×] δθ (+ δm)`,
//! `ŷ = A(q̂) v_ref` (eq. 6.41), taken as scalars `e · (y − ŷ) = (e × ŷ) · δθ (+ e · δm)`
//! along unit vectors `e`:
//! - **field**: along the body axes, three scalars (row `k` of `H` is row `k` of `[ŷ×]`, and
//!   1 on the magnetometer bias of axis `k`);
//! - **Sun** (a unit vector, two degrees of freedom): along the two unit vectors `e₁`, `e₂`
//!   normal to `ŷ` (Duff et al. 2017's basis: `H` rows `−e₂`, `e₁`), two scalars. Their
//!   information `(I − ŷŷᵀ)/σ²` is that of the three rows of `[ŷ×]` (Shuster 1989), for two
//!   thirds of the work (measured: the filter's step 441 494 → 411 121 cycles with the
//!   multiplier). The Sun's reference is the apparent Sun with the albedo
//!   ([`sun_reference`]), and each scalar has `e · A(q̂) ∂v_ref/∂a` on the albedo.
//!
//! Each is processed in turn with the
//! linearisation of the step (the innovation less `H δx`, the correction accumulated so far),
//! and the correction is applied once at the end: `q̂ ← q̂ ⊗ (1, δθ/2)`, renormalised,
//! `β̂ += δβ`, `m̂ += δm`, `â += δa` (kept within 0 ..= 1). For one scalar, with `u = P hᵀ`, `S = h u + R`, `K = u / S`:
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
//!   field model's error).
//!
//! The Sun's `σ²` per scalar along `e₁`, `e₂` is Shuster's (1989) measurement model of a unit
//! vector, `R = σ² (I − ŷŷᵀ)`, exactly.
//!
//! # Innovation gate
//! A scalar with `ν² > γ S` (`ν` its innovation, [`MekfConfig::gate_chi2`] = `γ`, a χ² with one
//! degree of freedom) is refused and counted; it also serves fault detection: a field with a
//! component refused at each of [`MekfConfig::refused_steps_to_restart`] steps in a row has its
//! bias forgotten (a stuck or failing magnetometer left it wrong), and a Sun refused as long, or
//! a field twice as long, restarts the filter from the two-vector solution (the estimate had
//! diverged, or a sensor has).
//!
//! # Use
//! [`step`] once a control step: it starts the filter from the step's two-vector attitude
//! (TRIAD, [`super::triad::pair_quaternion`]) when there is none, propagates it with the
//! gyros, updates it with the Sun and the field, and drops or restarts it when it is no longer
//! usable ([`Mekf::is_usable`]: the attitude 1σ within
//! [`MekfConfig::max_attitude_sigma_rad`]). The parts ([`Mekf::start`], [`Mekf::propagate`],
//! [`Mekf::update_sun`], [`Mekf::update_field`]) are public for tests and tools.
//!
//! **Cost** on the MSP430: `firmware/msp430-bench --groups parts`, case "step: attitude filter
//! (propagate + Sun + field)" (`docs/msp430.md`).
//!
//! **Accuracy** (f32): `cargo test --test mekf -- --nocapture` runs the filter in f32 beside
//! the same equations in f64 on one simulated hour; the estimates differ by at most the bound
//! stated in [`F32_ATTITUDE_BOUND_RAD`].

use crate::attitude::Quaternion;
use crate::fmath;
use crate::linalg::{arr, cross, div, dot, dot3, finite3, lin2, mat_vec, scale, sub_scaled, Vec3};

/// Error states: attitude (3), gyro bias (3), magnetometer bias (3), the Earth's albedo (1).
pub const STATES: usize = 10;
/// Entries of the packed upper triangle of `P`.
const PACKED: usize = STATES * (STATES + 1) / 2;
/// First index of the gyro-bias states.
const GYRO_BIAS: usize = 3;
/// First index of the magnetometer-bias states.
const MAG_BIAS: usize = 6;
/// Index of the albedo state.
const ALBEDO: usize = 9;

/// The largest difference between this f32 filter's attitude and the same equations in f64
/// over one simulated hour of `tests/mekf.rs`, rad (measured 7.4e-7 rad; the bound 1e-5).
pub const F32_ATTITUDE_BOUND_RAD: f32 = 1.0e-5;

/// Where row `i` of the packed upper triangle starts, `i (2n + 1 − i)/2`: a table, as the
/// MSP430's base instruction set has no multiply and the hot loops ask for every element.
/// (`packed_indices_cover_the_triangle_once` checks it.)
const ROW_START: [u8; STATES] = [0, 10, 19, 27, 34, 40, 45, 49, 52, 54];

/// Index of `P(i, j)` in the packed upper triangle, row by row (`PACKED`, outside it, for a
/// row past the state).
#[cfg_attr(target_arch = "msp430", inline(never))]
fn packed(i: usize, j: usize) -> usize {
    let (i, j) = if j >= i { (i, j) } else { (j, i) };
    ROW_START
        .get(i)
        .map_or(PACKED, |start| usize::from(*start) + (j - i))
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
    /// The Earth's albedo the Sun observation is corrected for ([`crate::env::albedo`]; 0: no
    /// correction).
    pub earth_albedo: f32,
    /// The initial 1σ of the albedo, a fraction of [`Self::earth_albedo`].
    pub albedo_relative_sigma: f32,
    /// `σ_a`: the albedo's random walk, 1/√s.
    pub albedo_walk_per_sqrt_s: f32,
    /// The cosine of the Sun sensors' field of view's half angle (the albedo they see).
    pub sun_sensor_cos_half_fov: f32,
}

impl MekfConfig {
    /// True if every figure is a positive finite number (the gate and the limits included).
    pub fn is_valid(&self) -> bool {
        [
            self.gyro_arw_rad_per_sqrt_s,
            self.gyro_bias_walk,
            self.mag_bias_walk_nt_per_sqrt_s,
            self.sun_noise_rad,
            self.sun_floor_rad,
            self.field_noise_nt,
            self.field_relative,
            self.initial_attitude_rad,
            self.initial_gyro_bias_radps,
            self.initial_mag_bias_nt,
            self.gate_chi2,
            self.max_attitude_sigma_rad,
        ]
        .iter()
        .all(|x| x.is_finite() && *x > 0.0)
            && self.refused_steps_to_restart > 0
            && self.earth_albedo >= 0.0
            && self.albedo_relative_sigma >= 0.0
            && self.earth_albedo.is_finite()
            && self.albedo_relative_sigma.is_finite()
            && self.albedo_walk_per_sqrt_s >= 0.0
            && self.albedo_walk_per_sqrt_s.is_finite()
    }
}

/// A Sun observation ([`Mekf::update_sun`], [`sun_reference`]).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct SunObservation {
    /// The sensors' averaged direction, body (unit).
    pub body: Vec3,
    /// The apparent Sun they are compared with, TEME (unit): the Sun and the albedo.
    pub reference_teme: Vec3,
    /// Its change with the albedo, TEME, per unit of albedo.
    pub d_reference_d_albedo: Vec3,
    /// The variance per axis, rad² ([`sun_variance_rad2`]).
    pub variance_rad2: f32,
}

/// What a vector observation adds beyond the attitude: the magnetometer bias (one per axis,
/// partial 1) or the albedo (one for the three axes, these partials, body).
#[derive(Copy, Clone, Debug, PartialEq)]
enum Extra {
    MagBias,
    Albedo(Vec3),
}

/// What one update did.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct UpdateOutcome {
    /// Scalar measurements taken.
    pub accepted: u8,
    /// Scalar measurements refused by the gate.
    pub refused: u8,
    /// The filter (re)started at this step from the two-vector attitude.
    pub started: bool,
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
    /// The Earth's albedo the Sun sensors see (0 ..= 1).
    pub albedo: f32,
    /// The packed upper triangle of the error covariance, row by row.
    p: [f32; PACKED],
    /// Steps in a row with a Sun scalar refused, and with a field scalar refused.
    sun_refused_steps: u8,
    field_refused_steps: u8,
    /// The tiles (bit `i`: tile `i`) whose magnetometers and gyros the bias estimates are of,
    /// and the steps in a row each sensor has come from another set.
    mag_tiles: u32,
    gyro_tiles: u32,
    mag_other_steps: u8,
    gyro_other_steps: u8,
    /// The last rate the gyros gave (less the bias), rad/s, and the steps in a row without one.
    last_rate_radps: Vec3,
    steps_without_rate: u8,
    /// The attitude correction of the last step's updates (the error state's `δθ` the Sun's
    /// and the field's applied, summed), body, rad: the stuck-gyro watch sums it about each
    /// gyro's axis ([`crate::attitude_node::stuck`]).
    pub correction_rad: Vec3,
}

/// Steps in a row a sensor must come from a new set of tiles before the filter takes the set
/// as the new one and forgets that sensor's bias ([`Mekf::forget_bias`]). A read missed for a
/// step or two (a time-out) is not a new set: the field of another set is not used meanwhile
/// (its bias is another), the rate is (one step of another gyro bias, ≤ 1e-4 rad/s, is
/// far below the rate's noise).
pub const STEPS_TO_NEW_SET: u8 = 5;

/// The 1σ change of the body rate over a step the filter propagates without the gyros (the
/// last rate held, for at most [`STEPS_TO_NEW_SET`] steps), rad/s: the tracking law's rate
/// changes by less than 1e-4 rad/s a step (the orbit rate is 1.1e-3 rad/s); ten times that.
pub const RATE_HELD_RADPS: f32 = 1.0e-3;

/// One control step's inputs to [`step`].
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct StepInputs {
    /// The gyros' fused rate, rad/s (body), if any.
    pub omega_body_radps: Option<Vec3>,
    /// The Sun ([`SunObservation`]).
    pub sun: Option<SunObservation>,
    /// The field: body (the magnetometers' fused field) and TEME (the model's), nT.
    pub field: Option<(Vec3, Vec3)>,
    /// The tiles (bit `i`: tile `i`) whose magnetometers gave the field.
    pub mag_tiles: u32,
    /// The tiles whose gyros gave the rate.
    pub gyro_tiles: u32,
    /// Seconds since the previous step.
    pub dt_s: f32,
}

/// One control step of the filter: started from the two-vector attitude (TRIAD of the Sun and
/// the field, the Sun exact: [`super::triad::pair_quaternion`], computed only then) when there
/// is no estimate; otherwise propagated with the gyros' rate and updated with the Sun and the field.
/// A bias whose set of sensors changed for [`STEPS_TO_NEW_SET`] steps is forgotten
/// ([`Mekf::forget_bias`]) before its sensors are used (the field of a set not yet taken is
/// not used); a step without a rate propagates the last one (for at most
/// [`STEPS_TO_NEW_SET`] steps, with [`RATE_HELD_RADPS`]); a step longer without one, or whose
/// result is unusable or has diverged ([`Mekf::diverged`]), restarts from the two-vector
/// attitude if there is one, else leaves no estimate. The estimate is updated in place;
/// returns what the updates did (none on a start).
#[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
pub fn step(
    config: &MekfConfig,
    estimate: &mut Option<Mekf>,
    inputs: &StepInputs,
) -> UpdateOutcome {
    // in place: the state is 300 B, and on the MSP430 each copy of it is stack
    if let Some(o) = estimate.as_mut().and_then(|f| f.advance(config, inputs)) {
        return o;
    }
    let two_vector = match (&inputs.sun, &inputs.field) {
        (Some(sun), Some((body, teme))) => {
            super::triad::pair_quaternion(&sun.body, &sun.reference_teme, body, teme)
        }
        _ => None,
    };
    match two_vector {
        Some(q) => {
            Mekf::start_in(estimate, config, q, inputs.mag_tiles, inputs.gyro_tiles);
            UpdateOutcome {
                started: true,
                ..UpdateOutcome::default()
            }
        }
        None => {
            *estimate = None;
            UpdateOutcome::default()
        }
    }
}

/// The Sun observation's variance, rad² per axis, from the lit sensors' incidence cosines
/// (`Σ 1/cos²θᵢ` over the `n` averaged, given as `inv_cos2_sum` and `n`; see the [module
/// docs](self)).
pub fn sun_variance_rad2(config: &MekfConfig, inv_cos2_sum: f32, n: u8) -> f32 {
    let n = f32::from(core::cmp::max(n, 1));
    let s0 = config.sun_noise_rad;
    let floor = config.sun_floor_rad;
    floor * floor + s0 * s0 * inv_cos2_sum / (n * n)
}

/// The apparent Sun the sensors' average is compared with, TEME (unit), and its change with
/// the albedo (per unit of albedo) ([`crate::env::albedo`]): the Sun's visible `fraction` plus
/// `albedo` × the irradiance of a unit albedo the lit sensors see (`albedo_teme`, the REF's:
/// [`crate::env::albedo::seen_by_lit_sensors`]). With `v = f ŝ + a D₁`, `u = v/|v|`:
/// `∂u/∂a = (D₁ − (u·D₁) u)/|v|`. Without `albedo_teme`: the Sun itself, no change.
#[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
pub fn sun_reference(
    sun_teme: &Vec3,
    fraction: f32,
    albedo_teme: Option<&Vec3>,
    albedo: f32,
) -> (Vec3, Vec3) {
    let Some(d1) = albedo_teme else {
        return (*sun_teme, Vec3::zeros());
    };
    let v = lin2(sun_teme, fraction, d1, albedo);
    let n = crate::linalg::norm(&v);
    if !(n > 0.0 && n.is_finite()) {
        return (*sun_teme, Vec3::zeros());
    }
    let u = div(&v, n);
    (u, div(&sub_scaled(d1, &u, dot(&u, d1)), n))
}

impl Mekf {
    /// A filter at `attitude` (a two-vector solution) with the configured initial 1σ, the
    /// biases zero.
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    pub fn start(config: &MekfConfig, attitude: Quaternion) -> Self {
        let mut filter = Self::EMPTY;
        filter.initialise(config, attitude, 0, 0);
        filter
    }

    /// Nothing: the initial value of a state built in place.
    /// (All zero, the attitude too, so that it is a fill, not a 300-B copy from flash.)
    const EMPTY: Self = Self {
        attitude: Quaternion {
            q0: 0.0,
            q1: 0.0,
            q2: 0.0,
            q3: 0.0,
        },
        gyro_bias_radps: Vec3::new(0.0, 0.0, 0.0),
        mag_bias_nt: Vec3::new(0.0, 0.0, 0.0),
        albedo: 0.0,
        p: [0.0; PACKED],
        sun_refused_steps: 0,
        field_refused_steps: 0,
        mag_tiles: 0,
        gyro_tiles: 0,
        mag_other_steps: 0,
        gyro_other_steps: 0,
        last_rate_radps: Vec3::new(0.0, 0.0, 0.0),
        steps_without_rate: 0,
        correction_rad: Vec3::new(0.0, 0.0, 0.0),
    };

    /// [`Self::start`] into `slot` in place, for the sensor sets `mag_tiles` and `gyro_tiles`
    /// (the state is 300 B: on the MSP430 a copy of it is stack).
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    fn start_in(
        slot: &mut Option<Self>,
        config: &MekfConfig,
        attitude: Quaternion,
        mag_tiles: u32,
        gyro_tiles: u32,
    ) {
        slot.insert(Self::EMPTY)
            .initialise(config, attitude, mag_tiles, gyro_tiles);
    }

    /// The start's state on an [`Self::EMPTY`] filter.
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    fn initialise(
        &mut self,
        config: &MekfConfig,
        attitude: Quaternion,
        mag_tiles: u32,
        gyro_tiles: u32,
    ) {
        let filter = self;
        filter.attitude = attitude;
        filter.albedo = config.earth_albedo;
        (filter.mag_tiles, filter.gyro_tiles) = (mag_tiles, gyro_tiles);
        let a = config.initial_attitude_rad;
        let b = config.initial_gyro_bias_radps;
        let m = config.initial_mag_bias_nt;
        let albedo = config.albedo_relative_sigma * config.earth_albedo;
        for i in 0..STATES {
            let s = match i {
                0..GYRO_BIAS => a,
                GYRO_BIAS..MAG_BIAS => b,
                MAG_BIAS..ALBEDO => m,
                // a state that never moves keeps a positive variance
                _ => fmath::max(albedo, 1e-6),
            };
            filter.set(i, i, s * s);
        }
    }

    /// `P(i, j)` (0 outside the state, which no caller asks).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn at(&self, i: usize, j: usize) -> f32 {
        self.p.get(packed(i, j)).copied().unwrap_or(0.0)
    }

    /// `P(i, j)` in place (a zero outside the matrix).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn entry(&self, i: usize, j: usize) -> &f32 {
        self.p.get(packed(i, j)).unwrap_or(&0.0)
    }

    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn set(&mut self, i: usize, j: usize, value: f32) {
        if let Some(e) = self.p.get_mut(packed(i, j)) {
            *e = value;
        }
    }

    /// The 1σ of each attitude error axis (body), rad: `√P(k, k)`.
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    pub fn attitude_sigma_rad(&self) -> Vec3 {
        Vec3::new(
            fmath::sqrt(self.at(0, 0)),
            fmath::sqrt(self.at(1, 1)),
            fmath::sqrt(self.at(2, 2)),
        )
    }

    /// The variance of error state `i` (`P(i, i)`; 0 beyond [`STATES`]).
    pub fn variance(&self, i: usize) -> f32 {
        self.at(i, i)
    }

    /// The covariance's diagonal: attitude (rad²), gyro bias (rad²/s²), magnetometer bias
    /// (nT²).
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    pub fn variances(&self) -> [f32; STATES] {
        let mut d = [0.0; STATES];
        for (i, v) in d.iter_mut().enumerate() {
            *v = self.at(i, i);
        }
        d
    }

    /// The full covariance, for tests and the ground (`P(i, j)`).
    #[cfg_attr(target_arch = "msp430", optimize(size))]
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
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    pub fn is_usable(&self, config: &MekfConfig) -> bool {
        let limit = config.max_attitude_sigma_rad;
        let healthy = self.p.iter().all(|v| v.is_finite())
            && (0..STATES).all(|i| self.at(i, i) > 0.0)
            && finite3(&self.gyro_bias_radps)
            && finite3(&self.mag_bias_nt);
        healthy && self.attitude_within(limit)
    }

    /// True if the attitude's largest 1σ is within `sigma_rad` (its variances within
    /// `sigma_rad²`; a NaN variance is not).
    pub fn attitude_within(&self, sigma_rad: f32) -> bool {
        (0..GYRO_BIAS).all(|i| sigma_rad * sigma_rad >= self.at(i, i))
    }

    /// The gyros' rate less the estimated bias, rad/s (body).
    pub fn rate_body_radps(&self, omega_body_radps: &Vec3) -> Vec3 {
        crate::linalg::sub(omega_body_radps, &self.gyro_bias_radps)
    }

    /// Adds `variance` (rad²/s²) to the gyro bias's covariance along the unit `axis` (body): a
    /// gyro held at a stuck word leaves the rate about its axis to the bias state, a random walk
    /// as fast as the body's rate changes ([`crate::attitude_node::stuck`]).
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    pub fn inflate_gyro_bias(&mut self, axis: &Vec3, variance: f32) {
        let a = [axis.x, axis.y, axis.z];
        for (i, ai) in a.iter().enumerate() {
            // (variance·aᵢ)·aⱼ
            let u = variance * ai;
            for (j, aj) in a.iter().enumerate().skip(i) {
                let (i, j) = (GYRO_BIAS + i, GYRO_BIAS + j);
                self.set(i, j, self.at(i, j) + u * aj);
            }
        }
    }

    /// The bias estimates of the magnetometers (`mag`) or the gyros (`!mag`) no longer apply
    /// (the set of tiles read changed): their covariance goes back to the initial 1σ and
    /// loses its correlations, so the next measurements move the bias, not the attitude.
    #[cfg_attr(target_arch = "msp430", optimize(size))]
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

    /// One step of [`step`] on an estimate: `None` if it must restart (no rate for too long,
    /// unusable, diverged).
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    fn advance(&mut self, config: &MekfConfig, inputs: &StepInputs) -> Option<UpdateOutcome> {
        match inputs.omega_body_radps {
            Some(w) => {
                if self.gyro_tiles == inputs.gyro_tiles {
                    self.gyro_other_steps = 0;
                } else {
                    self.gyro_other_steps = self.gyro_other_steps.saturating_add(1);
                    if self.gyro_other_steps >= STEPS_TO_NEW_SET {
                        self.forget_bias(config, false);
                        (self.gyro_tiles, self.gyro_other_steps) = (inputs.gyro_tiles, 0);
                    }
                }
                self.steps_without_rate = 0;
                self.last_rate_radps = self.rate_body_radps(&w);
                if !self.propagate(config, &w, inputs.dt_s) {
                    return None;
                }
            }
            // a step without the gyros (a missed read): the last rate held, its change unknown
            None if STEPS_TO_NEW_SET > self.steps_without_rate => {
                self.steps_without_rate += 1;
                let w = self.last_rate_radps + self.gyro_bias_radps;
                if !self.propagate(config, &w, inputs.dt_s) {
                    return None;
                }
                let held = RATE_HELD_RADPS * inputs.dt_s;
                for i in 0..GYRO_BIAS {
                    self.set(i, i, self.at(i, i) + held * held);
                }
            }
            None => return None,
        }
        let mut outcome = UpdateOutcome::default();
        self.correction_rad = Vec3::zeros();
        if let Some(sun) = &inputs.sun {
            outcome = self.update_sun(config, sun);
        }
        if let Some((body, teme)) = &inputs.field {
            let mut same = self.mag_tiles == inputs.mag_tiles;
            if same {
                self.mag_other_steps = 0;
            } else {
                self.mag_other_steps = self.mag_other_steps.saturating_add(1);
                if self.mag_other_steps >= STEPS_TO_NEW_SET {
                    self.forget_bias(config, true);
                    (self.mag_tiles, self.mag_other_steps) = (inputs.mag_tiles, 0);
                    same = true;
                }
            }
            if same {
                let o = self.update_field(config, body, teme);
                outcome.accepted += o.accepted;
                outcome.refused += o.refused;
            }
        }
        (!self.diverged(config) && self.is_usable(config)).then_some(outcome)
    }

    /// Propagation over `dt_s` with the gyros' rate (see the [module docs](self)), in place;
    /// false if the result is not usable (a non-finite rate or state, the attitude 1σ past its
    /// limit).
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    pub fn propagate(&mut self, config: &MekfConfig, omega_body_radps: &Vec3, dt_s: f32) -> bool {
        let w = self.rate_body_radps(omega_body_radps);
        let half = scale(&w, 0.5 * dt_s);
        let dq = Quaternion {
            q0: 1.0,
            q1: half.x,
            q2: half.y,
            q3: half.z,
        };
        let q = self.attitude.mul(&dq);
        match Quaternion::new_normalize(q.q0, q.q1, q.q2, q.q3) {
            Some(q) => self.attitude = q,
            None => return false,
        }
        // Φ P: the attitude rows become x − (ω̂Δt) × x − Δt·(gyro-bias rows), column by column
        let w_dt = scale(&w, dt_s);
        let mut rows = [[0.0f32; STATES]; 3];
        let [r0, r1, r2] = &mut rows;
        for (j, ((e0, e1), e2)) in r0
            .iter_mut()
            .zip(r1.iter_mut())
            .zip(r2.iter_mut())
            .enumerate()
        {
            let mut column = [0.0f32; 2 * GYRO_BIAS];
            for (i, e) in column.iter_mut().enumerate() {
                *e = self.at(i, j);
            }
            let y = phi(&column, &w_dt, dt_s);
            (*e0, *e1, *e2) = (y.x, y.y, y.z);
        }
        // (Φ P) Φᵀ: the same on the attitude columns; rows beyond the attitude's are P's own
        for (i, row) in rows.iter().enumerate() {
            // `filter`, not `skip`: `Skip`'s `next` is 102 B of MSP430 code of its own
            for (j, e) in row.iter().enumerate().filter(|(j, _)| *j >= GYRO_BIAS) {
                self.set(i, j, *e);
            }
            if let Some(head) = row.first_chunk() {
                let y = phi(head, &w_dt, dt_s);
                for (j, e) in arr(&y).iter().enumerate().filter(|(j, _)| *j >= i) {
                    self.set(i, j, *e);
                }
            }
        }
        let (v, u, m, a) = (
            config.gyro_arw_rad_per_sqrt_s,
            config.gyro_bias_walk,
            config.mag_bias_walk_nt_per_sqrt_s,
            config.albedo_walk_per_sqrt_s,
        );
        let q_att = v * v * dt_s + u * u * dt_s * dt_s * dt_s / 3.0;
        for i in 0..STATES {
            let add = match i {
                0..GYRO_BIAS => q_att,
                GYRO_BIAS..MAG_BIAS => u * u * dt_s,
                MAG_BIAS..ALBEDO => m * m * dt_s,
                _ => a * a * dt_s,
            };
            self.set(i, i, self.at(i, i) + add);
        }
        self.is_usable(config)
    }

    /// The Sun's update with `sun` ([`SunObservation`]: the sensors' direction, the apparent
    /// Sun and its change with the albedo, the variance).
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    pub fn update_sun(&mut self, config: &MekfConfig, sun: &SunObservation) -> UpdateOutcome {
        let a = self.attitude.to_dcm();
        let predicted = mat_vec(a.matrix(), &sun.reference_teme);
        let d_albedo = mat_vec(a.matrix(), &sun.d_reference_d_albedo);
        // two scalars in the plane normal to the unit ŷ (see the module docs)
        // (an array in place: on the MSP430 each copy of a vector is a `memcpy`)
        let along = tangent_basis(&predicted);
        let outcome = self.update_vector(
            config,
            &along,
            &sun.body,
            &predicted,
            sun.variance_rad2,
            Extra::Albedo(d_albedo),
        );
        self.sun_refused_steps = count_refused(self.sun_refused_steps, &outcome);
        outcome
    }

    /// The field's update: `b_body_nt` (the magnetometers' fused field) and `b_teme_nt` (the
    /// model's), with the magnetometer bias.
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    pub fn update_field(
        &mut self,
        config: &MekfConfig,
        b_body_nt: &Vec3,
        b_teme_nt: &Vec3,
    ) -> UpdateOutcome {
        // the attitude after the Sun's correction, its own matrix: a sequential update
        // linearises each measurement about the estimate the one before left
        let predicted = mat_vec(self.attitude.to_dcm().matrix(), b_teme_nt);
        let k = config.field_relative;
        let s = config.field_noise_nt;
        let variance = s * s + k * k * dot(b_teme_nt, b_teme_nt);
        let outcome = self.update_vector(
            config,
            &AXES,
            b_body_nt,
            &predicted,
            variance,
            Extra::MagBias,
        );
        self.field_refused_steps = count_refused(self.field_refused_steps, &outcome);
        // the field refused for a while: first its bias is doubted (a stuck or failing sensor
        // leaves it wrong), then, refused as long again, the whole estimate (`diverged`)
        if self.field_refused_steps == config.refused_steps_to_restart {
            self.forget_bias(config, true);
        }
        outcome
    }

    /// True when the Sun has had a measurement refused at each of
    /// [`MekfConfig::refused_steps_to_restart`] steps in a row, or the field at each of twice as
    /// many (its bias is forgotten at the first count: [`Self::update_field`]).
    pub fn diverged(&self, config: &MekfConfig) -> bool {
        let n = config.refused_steps_to_restart;
        self.sun_refused_steps >= n || self.field_refused_steps >= n.saturating_mul(2)
    }

    /// The scalar updates with `y` (`measured`) against `ŷ` (`predicted`, + the magnetometer
    /// bias for the field) along each of the unit vectors `along` (body): `e · (y − ŷ)`
    /// against `(e × ŷ) · δθ`, with `e` on the magnetometer bias of its axis or `e · ∂ŷ/∂a` on
    /// the albedo; then the correction applied.
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    fn update_vector(
        &mut self,
        config: &MekfConfig,
        along: &[Vec3],
        measured: &Vec3,
        predicted: &Vec3,
        variance: f32,
        extra: Extra,
    ) -> UpdateOutcome {
        let mut dx = [0.0f32; STATES];
        let mut outcome = UpdateOutcome::default();
        let bias = match extra {
            Extra::MagBias => self.mag_bias_nt,
            Extra::Albedo(_) => Vec3::zeros(),
        };
        let residual = *measured - predicted - bias;
        for (k, e) in along.iter().enumerate() {
            let b = match extra {
                Extra::MagBias => (MAG_BIAS + k, 1.0),
                Extra::Albedo(d) => (ALBEDO, dot(e, &d)),
            };
            let h = cross(e, predicted);
            if self.scalar_update(config, &mut dx, &h, b, dot(e, &residual), variance) {
                outcome.accepted += 1;
            } else {
                outcome.refused += 1;
            }
        }
        self.apply(&dx);
        outcome
    }

    /// One scalar measurement `residual = h δθ + c δx_e + noise` of variance `r` (`extra` =
    /// `(e, c)`: a magnetometer bias with `c = 1`, or the albedo): gated, then the Joseph-form
    /// update of `P` and the correction accumulated in `dx`. False if refused.
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    fn scalar_update(
        &mut self,
        config: &MekfConfig,
        dx: &mut [f32; STATES],
        h: &Vec3,
        extra: (usize, f32),
        residual: f32,
        r: f32,
    ) -> bool {
        let (e, c) = extra;
        // u = P hᵀ
        let mut u = [0.0f32; STATES];
        for (i, ui) in u.iter_mut().enumerate() {
            *ui = self.row_dot(i, h, e, c);
        }
        let s = h_dot(&u, h, e, c) + r;
        let nu = residual - h_dot(dx, h, e, c);
        if !(s > 0.0) || !(config.gate_chi2 * s >= nu * nu) {
            return false;
        }
        // K = u · (1/S): one division (the Joseph form absorbs its rounding); w = S K − u
        let inv_s = 1.0 / s;
        let mut k = [0.0f32; STATES];
        let mut w = [0.0f32; STATES];
        for (((ki, wi), ui), di) in k
            .iter_mut()
            .zip(w.iter_mut())
            .zip(u.iter())
            .zip(dx.iter_mut())
        {
            *ki = ui * inv_s;
            *di += *ki * nu;
            *wi = s * *ki - ui;
        }
        // Joseph form: P + K wᵀ − u Kᵀ, on the upper triangle row by row
        let mut p = self.p.iter_mut();
        for (i, (ki, ui)) in k.iter().zip(u.iter()).enumerate() {
            for (kj, wj) in k.iter().zip(w.iter()).skip(i) {
                if let Some(p) = p.next() {
                    *p += ki * wj - ui * kj;
                }
            }
        }
        true
    }

    /// `Σⱼ P(i, j) hⱼ` for the row `h = (h, 0…, c at e)`.
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn row_dot(&self, i: usize, h: &Vec3, e: usize, c: f32) -> f32 {
        dot3(self.entry(i, 0), self.entry(i, 1), self.entry(i, 2), h) + c * self.at(i, e)
    }

    /// The accumulated correction applied to the estimate (the reset of the error state).
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    fn apply(&mut self, dx: &[f32; STATES]) {
        let dq = Quaternion {
            q0: 1.0,
            q1: 0.5 * dx[0],
            q2: 0.5 * dx[1],
            q3: 0.5 * dx[2],
        };
        self.correction_rad += Vec3::new(dx[0], dx[1], dx[2]);
        let q = self.attitude.mul(&dq);
        if let Some(q) = Quaternion::new_normalize(q.q0, q.q1, q.q2, q.q3) {
            self.attitude = q;
        }
        self.gyro_bias_radps += Vec3::new(dx[3], dx[4], dx[5]);
        self.mag_bias_nt += Vec3::new(dx[6], dx[7], dx[8]);
        // an albedo is within 0 ..= 1
        self.albedo = fmath::min(fmath::max(self.albedo + dx[9], 0.0), 1.0);
    }
}

/// The body axes: the field's scalars are its components.
static AXES: [Vec3; 3] = [
    Vec3::new(1.0, 0.0, 0.0),
    Vec3::new(0.0, 1.0, 0.0),
    Vec3::new(0.0, 0.0, 1.0),
];

/// Two unit vectors `(e₁, e₂)` completing the unit `p` to a right-handed orthonormal basis
/// `(e₁, e₂, p)`, without a square root or a singular direction: Duff et al., "Building an
/// Orthonormal Basis, Revisited", JCGT 6(1), 2017. Measured (f32): `|e₁|² − 1`, `|e₂|² − 1`,
/// `e₁·e₂`, `e₁·p`, `e₂·p` and each component of `e₁ × e₂ − p` within 2.8e-7 over 100 000 unit
/// vectors, the poles included (`tangent_basis_is_orthonormal`, bound 6e-7).
#[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
fn tangent_basis(p: &Vec3) -> [Vec3; 2] {
    // with s = ±1 the sign of p_z: a = −1/(s + p_z), t = s p_x a;
    // e₁ = (1 + s p_x² a, s p_x p_y a, −s p_x), e₂ = (p_x p_y a, s + p_y² a, −p_y)
    let negative = !(p.z >= 0.0);
    let s = if negative { -1.0 } else { 1.0 };
    let a = -1.0 / (s + p.z);
    let xa = p.x * a;
    let t = if negative { -xa } else { xa };
    let minus_sx = if negative { p.x } else { -p.x };
    [
        Vec3::new(1.0 + p.x * t, p.y * t, minus_sx),
        Vec3::new(xa * p.y, s + p.y * (p.y * a), -p.y),
    ]
}

/// `h · v` for the row `h = (h, 0…, c at e)`.
#[cfg_attr(target_arch = "msp430", inline(never))]
fn h_dot(v: &[f32; STATES], h: &Vec3, e: usize, c: f32) -> f32 {
    dot3(&v[0], &v[1], &v[2], h) + c * v.get(e).copied().unwrap_or(0.0)
}

/// `x − a × x − Δt·b`: one column (or row) of `Φ P` on the attitude states, with `a = ω̂Δt`,
/// `(x, b)` its first six entries (attitude, gyro bias), read in place.
#[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
fn phi(xb: &[f32; 2 * GYRO_BIAS], a: &Vec3, dt_s: f32) -> Vec3 {
    let [x1, x2, x3, b @ ..] = xb;
    let x = Vec3::new(*x1, *x2, *x3);
    let c = cross(a, &x);
    let [b1, b2, b3] = b;
    Vec3::new(
        x.x - c.x - dt_s * b1,
        x.y - c.y - dt_s * b2,
        x.z - c.z - dt_s * b3,
    )
}

/// Steps in a row with a scalar of a sensor refused (a step with none refused resets it).
fn count_refused(steps: u8, outcome: &UpdateOutcome) -> u8 {
    if outcome.refused > 0 {
        steps.saturating_add(1)
    } else {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `tangent_basis` over unit vectors spread over the sphere (a fixed sequence), the poles
    /// and the `p_z` sign change included: orthonormal and right-handed with `p` to f32
    /// rounding (the bound its docs state).
    #[test]
    fn tangent_basis_is_orthonormal() {
        let mut state = 0x2545_f491_u32;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state as f32 / u32::MAX as f32 * 2.0 - 1.0
        };
        let mut cases = [
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, -1.0, 0.0),
            Vec3::new(0.6, 0.8, 0.0),
            Vec3::new(0.6, 0.0, -0.8),
            Vec3::new(0.8, 0.6, 1e-7),
            Vec3::new(-0.8, 0.6, -1e-7),
        ]
        .to_vec();
        while cases.len() < 100_000 {
            let v = Vec3::new(next(), next(), next());
            let n = crate::linalg::norm(&v);
            if n > 0.1 && n <= 1.0 {
                cases.push(div(&v, n));
            }
        }
        let mut worst = 0.0f32;
        for p in &cases {
            let [e1, e2] = tangent_basis(p);
            let third = cross(&e1, &e2) - p;
            for err in [
                dot(&e1, &e1) - 1.0,
                dot(&e2, &e2) - 1.0,
                dot(&e1, &e2),
                dot(&e1, p),
                dot(&e2, p),
                third.x,
                third.y,
                third.z,
            ] {
                worst = fmath::max(worst, fmath::abs(err));
            }
        }
        println!("tangent basis: worst orthonormality error {worst:.2e}");
        assert!(worst < 6e-7, "{worst}");
    }

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
