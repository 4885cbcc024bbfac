//! The flight configuration: the one satellite the firmware flies, defined once.
//!
//! The MSP430 firmware (`firmware/`) runs [`FlightLoop`] over [`CONFIG`], and the host
//! simulator's scenarios `detumble`, `sun-safe`, `tracking`, `failed-tile` and `slew`
//! (`acs::host::sim::scenarios`) fly the same constant through the same loop, their truth's
//! spacecraft built from it, so what `acs sim` measures is what flies. Everything here is
//! `const`: on the target [`CONFIG`] is a `static` in flash and only the loop's run-time state
//! takes RAM.
//!
//! | item | value | source |
//! |---|---|---|
//! | tiles | the thesis's cube: one telecom and five power tiles ([`crate::tiles::CUBE_THESIS`]) | seed 000 §1.1 |
//! | inertia | diag(0.010, 0.012, 0.014) kg·m², body axes principal | AraMiS 1U class, seed 000 §4.2 order of magnitude |
//! | wheels | one per power tile, ±1 mN·m·s | seed 000 §9 (tile wheel) |
//! | wheel torque | 0.23 mN·m about each body axis: one wheel's ([`WHEEL_TORQUE_NM`]) | class (CubeWheel Small) |
//! | coils | three, along body x, y, z, ±0.2 A·m² | seed 002 §8 (coil sizing) |
//! | field model | IGRF-14 degree 13 (the full model), 2025–2030, extrapolated to 2035 (flagged) ([`crate::env::igrf::FLIGHT`]: only the interval it evaluates, 1 560 B of tables) | issue #17 product decision (degree 8 until issue #29 item 6) |
//! | Sun and shadow models | the thesis's Sun (Schlyter, 46.9″) and the cylindrical shadow, in the loop ([`crate::acs_loop`]) | issue #17: flash |
//! | control period | 1 s | seed 000 §1.5 |
//! | tracking | `ω_n` = [`TRACKING_BANDWIDTH_RADPS`] = 0.5 rad/s, `ζ` = 0.9 | below |
//! | attitude filter | the MEKF of [`crate::determination::mekf`], tuned from the sensors' classes ([`FILTER`]), started by TRIAD with the Sun exact | issue #30 |
//!
//! **Tracking bandwidth.** The PD law's steady error under a constant disturbance `τ` is
//! `τ / (I ω_n²)` per axis ([`crate::control::tracking`]: `K_p = 2 ω_n² I`, `q_e ≈ θ/2`).
//! Against seed 004's worst-case drag torque on a 500 km orbit (1.2e-6 N·m) and the smallest
//! moment, 0.010 kg·m², 0.25 rad/s leaves 0.11° and 0.5 rad/s 0.028° (the error issue #8's
//! 3U, 0.042 kg·m², had at 0.25 rad/s). 0.5 rad/s is still 12.6 control periods per natural
//! period. Measured in the `tracking` scenario (ideal truth, the loop of
//! `tests/closed_loop.rs` with the bandwidth changed; the worst pointing error from 600 s after
//! settling, seed 5 and the mean over seeds 1–24), both with Wahba's weights below, 0.25 → 0.5
//! rad/s: 0.110° → 0.087°, mean 0.139° → 0.121°; the control part (filtered attitude against
//! the target) 0.144° → 0.103° (with the degree-8 field model flown when it was decided, before
//! issue #29: 0.209° → 0.176°, mean 0.218° → 0.184°, control part 0.141° → 0.100°).
//!
//! **Wahba weights** ([`SUN_WEIGHT`], [`FIELD_WEIGHT`]): `σ⁻²` of the Sun (1 mrad) and field
//! (30′, the accuracy of IGRF itself in declination and inclination, seed 000 §3.1) directions
//! for Wahba's problem on the ground and in the examples (`examples/determine.rs`). The loop
//! flew them until issue #30; its filter now weighs each observation by its own noise
//! ([`FILTER`]).
//!
//! Attitudes follow [`crate::attitude`]: `v_body = A · v_ref`, reference TEME of date.

use crate::acs_loop::{AcsConfig, AcsLoop};
use crate::control::bdot::BdotConfig;
use crate::control::principal_axes::PrincipalAxes;
use crate::control::slew::SlewLimits;
use crate::control::sun_safe::SunSafeGains;
use crate::control::tracking::TrackingGains;
use crate::control::wheels::Wheel;
use crate::determination::mekf::MekfConfig;
use crate::env::igrf::{coefficient_count, Degree, ModelId, FLIGHT};
use crate::linalg::{Mat3, Vec3};
use crate::two_node::TwoNodeLoop;

/// The number of tiles of the flight configuration (the thesis's cube): the loop is sized to it.
pub const TILES: usize = 6;

/// The flight degree of the IGRF model: all the flight tables hold (13, the full model; 8 before
/// issue #29).
pub const IGRF_DEGREE: Degree = FLIGHT.degree();

/// Room for the IGRF coefficients of the flight degree: 195 (780 B of stack while the field is
/// evaluated; the loop keeps none between steps).
pub const FIELD_COEFFS: usize = coefficient_count(IGRF_DEGREE.get());

/// The flight software as the host flies it: the reference and attitude nodes of the two flight
/// images, composed ([`crate::two_node`]): six tiles, the flight degree's coefficients. The
/// simulator, the `acs` tool, the campaigns and the tests fly it.
pub type FlightLoop = TwoNodeLoop<'static, TILES, FIELD_COEFFS>;

/// The one-image loop over the same configuration ([`AcsLoop`]: bit for bit the two nodes,
/// `tests/two_node.rs`): the benchmark's one-call step and the one-image composition that fits
/// no part.
pub type OneImageLoop = AcsLoop<'static, TILES, FIELD_COEFFS>;

/// The principal moments of inertia, kg·m²: the body axes are principal axes.
pub const INERTIA_DIAGONAL_KGM2: [f32; 3] = [0.010, 0.012, 0.014];

/// Momentum limit of each reaction wheel, kg·m²/s.
pub const WHEEL_LIMIT_NMS: f32 = 1.0e-3;

/// Torque of one reaction wheel, N·m: the class of the 1–2 mN·m·s CubeSat wheels (CubeSpace
/// CubeWheel Small, 0.23 mN·m). The loop asks at most this about each body axis
/// ([`AcsConfig::wheel_torque_nm`]): one wheel's torque, which the y and z axes (two wheels
/// each) keep with one of their tiles failed.
pub const WHEEL_TORQUE_NM: f32 = 2.3e-4;
const _: () = assert!(WHEEL_TORQUE_NM > 0.0 && !(WHEEL_TORQUE_NM >= f32::INFINITY));

/// Dipole limit of each magnetorquer coil, A·m².
pub const COIL_LIMIT_AM2: f32 = 0.2;

/// The control period, s.
pub const CONTROL_PERIOD_S: f32 = 1.0;

/// Natural frequency of the tracking law, rad/s (damping 0.9; see the [module docs](self)).
pub const TRACKING_BANDWIDTH_RADPS: f32 = 0.5;

/// 1σ direction error of the Sun observation, rad.
pub const SUN_SIGMA_RAD: f32 = 1.0e-3;

/// 1σ direction error of the field observation, rad: IGRF's 30′ (seed 000 §3.1).
pub const FIELD_SIGMA_RAD: f32 = 30.0 / 60.0 * core::f32::consts::PI / 180.0;

/// Wahba weight of the Sun observation, `σ⁻²` (rad⁻²): 1e6.
pub const SUN_WEIGHT: f32 = 1.0 / (SUN_SIGMA_RAD * SUN_SIGMA_RAD);

/// Wahba weight of the field observation, `σ⁻²` (rad⁻²): 1.31e4.
pub const FIELD_WEIGHT: f32 = 1.0 / (FIELD_SIGMA_RAD * FIELD_SIGMA_RAD);

/// The attitude filter's tuning ([`crate::determination::mekf`]), from the sensors' classes
/// (the figures of their data sheets, not the simulator's draws):
///
/// | figure | value | source |
/// |---|---|---|
/// | gyro angle random walk `σ_v` | 2.6e-4 rad/√s (0.015 °/√s) | ADXRS453 class (0.015 °/s/√Hz) |
/// | gyro bias walk `σ_u` | 3.5e-6 rad/s/√s | its 16 °/h bias instability over a 1 000 s correlation time: `σ √(2/τ)` |
/// | magnetometer bias walk `σ_m` | 0.5 nT/√s | assumption: the rotors' fields with the wheel speeds, the offsets with temperature (16 nT in 1 000 s) |
/// | Sun noise `σ₀` | 3.5e-4 rad (0.02°) at normal incidence, × 1/cos θ | NFSS-411 class (seed 004 §2.7) |
/// | Sun floor | 2.5e-3 rad (0.14°): calibration residual 0.1° RMS ⊕ alignment 0.1° | NFSS-411 (< 0.1° RMS); tile and sensor alignment |
/// | field noise | 50 nT ⊕ 0.5 % of `|B|` per axis | the magnetometers' noise and 10 nT word, the field model beyond degree 13 and the spacecraft's fields (absolute); scale factors and misalignment (relative) |
/// | initial 1σ | 0.05 rad, 2e-4 rad/s, 300 nT | a two-vector solution's error; the gyros' turn-on bias and instability; offsets and the residual dipole |
/// | gate | χ² = 16 (4σ, one scalar in 16 000 refused by chance) | |
/// | restart | 10 steps with a sensor's every scalar refused | |
/// | usable while | the attitude 1σ ≤ 0.1 rad (5.7°) | |
/// | Sun sensors' field of view | 70° half angle (cos = 0.342) | NFSS-411 class (140°) |
/// | Earth albedo | 0.30 ± 50 % at the start, a random walk of 1e-3/√s (0.03 in 1 000 s) | the Earth's mean Bond albedo; the local albedo ranges over 0.1–0.8 (oceans to clouds and ice) |
pub const FILTER: MekfConfig = MekfConfig {
    gyro_arw_rad_per_sqrt_s: 2.6e-4,
    gyro_bias_walk: 3.5e-6,
    mag_bias_walk_nt_per_sqrt_s: 0.05,
    sun_noise_rad: 3.5e-4,
    sun_floor_rad: 2.5e-3,
    field_noise_nt: 50.0,
    field_relative: 5.0e-3,
    initial_attitude_rad: 0.05,
    initial_gyro_bias_radps: 2.0e-4,
    initial_mag_bias_nt: 300.0,
    gate_chi2: 16.0,
    refused_steps_to_restart: 10,
    max_attitude_sigma_rad: 0.1,
    earth_albedo: 0.30,
    albedo_relative_sigma: 0.5,
    albedo_walk_per_sqrt_s: 1.0e-3,
    sun_sensor_cos_half_fov: 0.342,
};

/// The principal axes of a diagonal inertia tensor: `E = I`, the moments in body-axis order
/// (what [`crate::control::principal_axes::principal_axes`] returns for it; a test checks it),
/// without its eigen-decomposition on board.
pub const fn principal_axes_of_diagonal(moments: &[f32; 3]) -> PrincipalAxes {
    let [a, b, c] = *moments;
    PrincipalAxes {
        e: Mat3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
        moments: Vec3::new(a, b, c),
        inertia_body: Mat3::new(a, 0.0, 0.0, 0.0, b, 0.0, 0.0, 0.0, c),
    }
}

/// One working magnetorquer coil along the body axis `(x, y, z)`.
const fn coil(x: f32, y: f32, z: f32) -> Wheel {
    Wheel {
        axis_body: Vec3::new(x, y, z),
        limit: COIL_LIMIT_AM2,
        working: true,
    }
}

/// The flight configuration (see the [module docs](self)).
pub static CONFIG: AcsConfig<TILES> = {
    let axes = principal_axes_of_diagonal(&INERTIA_DIAGONAL_KGM2);
    let i_max = INERTIA_DIAGONAL_KGM2[2];
    AcsConfig {
        tiles: heapless::Vec::from_array(crate::tiles::CUBE_THESIS),
        tracking: TrackingGains::from_bandwidth(&axes.inertia_body, TRACKING_BANDWIDTH_RADPS, 0.9),
        // the tracking law's 0.5 rad/s at the 1 s period: the discrete loop's ω T at its limit
        slew_gain_factor: 1.0,
        axes,
        coils: heapless::Vec::from_array([
            coil(1.0, 0.0, 0.0),
            coil(0.0, 1.0, 0.0),
            coil(0.0, 0.0, 1.0),
        ]),
        wheel_limit_nms: WHEEL_LIMIT_NMS,
        wheel_torque_nm: Vec3::new(WHEEL_TORQUE_NM, WHEEL_TORQUE_NM, WHEEL_TORQUE_NM),
        bdot: BdotConfig {
            gain: 3.0e4,
            max_dipole_am2: Vec3::new(COIL_LIMIT_AM2, COIL_LIMIT_AM2, COIL_LIMIT_AM2),
        },
        sun_safe: SunSafeGains {
            kp_nm: 2.0 * 0.05 * 0.05 * i_max,
            kd_nms: 2.0 * 0.05 * i_max,
        },
        sun_axis_body: Vec3::new(0.0, 0.0, 1.0),
        slew_limits: SlewLimits {
            l_max: WHEEL_LIMIT_NMS,
            l_min: 1e-7,
            t_min: 0.3,
            // not the thesis's 0.85: the wheels carry momentum when a slew is commanded and
            // the closed loop's feedback adds to it; at 0.85 a wheel saturated in 0.5 % of a
            // 10 000-run `slew` campaign and the feedback, integrated into the momentum it could
            // not deliver, overshot the target by up to 24° (at 0.7, 3 000 runs: 1.49° at worst)
            default_fraction: 0.7,
            wheels_per_axis: [1, 2, 2],
        },
        slew_pause_s: 5.0,
        control_period_s: CONTROL_PERIOD_S,
        dumping_gain_per_s: 1e-3,
        detumble_enter_radps: 0.5,
        detumble_exit_radps: 0.008_7,
        igrf_model: ModelId::Flight,
        igrf_degree: IGRF_DEGREE,
        filter: FILTER,
    }
};
