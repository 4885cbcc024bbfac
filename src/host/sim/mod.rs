//! The host simulator: f64 truth dynamics, environment and simulated tiles that fly the flight
//! loop ([`crate::acs_loop`]) unchanged, through the same [`TileBus`] trait as the hardware.
//!
//! Two truths ([`realistic::TruthLevel`], `acs sim SCENARIO --truth ideal|realistic`):
//! - the **realistic** truth (the default, [`realistic`]): a field that is not the flight model
//!   (IGRF-14 at degree 13 plus a 100 nT RMS unmodelled field), the spacecraft's own fields at
//!   the magnetometers, Earth albedo, and sensors and actuators as real hardware behaves, each
//!   effect a parameter of one table per device (`docs/simulator.md` lists them with values and
//!   sources);
//! - the **ideal** truth (`SimConfig::realism` = `None`): the simulator as it was before issue
//!   #18, bit for bit: the truth field is IGRF itself, the sensors have the scenario's
//!   [`SensorNoise`], wheels slew to their command at the torque limit, coils take their command
//!   at once.
//!
//! # Truth models
//! | what | model |
//! |---|---|
//! | orbit | the `sgp4` crate (f64, Vallado's SGP4, WGS-72), independent of the flight SGP4 |
//! | attitude | `q̇ = ½ q ⊗ (0, ω)` (scalar-first, reference TEME → body, [`crate::attitude`]) |
//! | rigid body + wheels | `I ω̇ = τ − ω × (I ω + h) − ḣ`, RK4 at [`SimConfig::substep_s`] |
//! | wheels | ideal: each wheel slews to its commanded momentum at up to `wheel_max_torque_nm`; realistic: [`realistic::WheelModel`] |
//! | coils | ideal: the commanded dipole; realistic: [`realistic::CoilModel`], commanded at the step's actuation instant |
//! | magnetic torque | `m × B`, B the truth field in TEME (IGRF-14 degree 13 through GMST; plus the unmodelled field in the realistic truth) |
//! | gravity gradient | `3μ/r³ ô × (I ô)` (seed 004 eq. A.13) |
//! | aerodynamic | `½ ρ C_d A v² (c_p × v̂)`, exponential atmosphere (60 km scale height; 4.38e-12 kg/m³ at 500 km, seed 004's solar maximum; realistic: [`realistic::SolarActivity`], default the same maximum) |
//! | solar pressure | `p_R A (1+q) (c_p × ŝ)`, off in the umbra |
//! | residual dipole | `m_res × B` |
//! Defaults follow seed 004 (3U: `C_d = 2.5`, 1.5× the largest face, 72.8 mm lever arm,
//! `m_res = 4e-3 A·m²`).
//!
//! The Sun and the IGRF part of the field use the crate's own f32 models, evaluated once per
//! control period, in both truths: the precise Sun is within 2.22″ (RMS 0.82″) of DE421 and
//! IGRF-14 within 0.2 nT of ppigrf (`docs/accuracy.md`, "Sun direction" and "Geomagnetic field"),
//! far below what the attitude figures resolve; the orbit is the independent `sgp4` crate (a port
//! of Vallado's f64 SGP4), which reproduces Vallado's reference ephemerides (`tests/data/sgp4`) to
//! 2e-6 m (`docs/accuracy.md`, "SGP4"). What the
//! realistic truth makes independent of the flight models is what they leave out: the field
//! beyond IGRF (and, before issue #29, beyond the flight model's degree 8), albedo, the
//! spacecraft's own fields, the devices' errors.
//!
//! # Simulated tiles
//! Each tile's sensors see the truth through its orientation: Sun angles, magnetometer, gyro,
//! int16 quantisation in the units of note 000 §1.3, random dropouts and failures from a given
//! time. Ideal truth: Sun angles only within `sun_fov_rad` of the normal and outside the umbra,
//! Gaussian noise and constant biases ([`SensorNoise`]), from a seeded sequential generator.
//! Realistic truth: the device models of [`realistic::devices`], sampled at the step's read
//! instant, with counter-based random draws (a pure function of the seed, the device and the
//! step: the readings do not depend on which loop reads them or in what order). Runs are
//! reproducible.
//!
//! # Wheel momentum read-back
//! [`Simulator::wheel_momentum_nms`] is the simulator side of the HAL read-back issue #18 asks
//! for: once [`TileBus`] has `read_wheel_momentum`, the simulator implements it by that call.

pub mod campaign;
pub mod faults;
pub mod pil;
pub mod plan_flight;
pub mod plot;
pub mod realistic;
pub mod rehearsal;
pub mod scenario_file;
pub mod scenarios;

use std::f64::consts::PI;

use crate::acs_loop::{Command, Mode, StepReport};
use crate::attitude::Quaternion;
use crate::env::eclipse::conical;
use crate::env::igrf::{Degree, Igrf, FULL};
use crate::env::sun::precise;
use crate::hal::{ErrorKind, TileBus};
use crate::linalg::{Mat3d, Vec3, Vec3d};
use crate::tiles::{sun_angles_of_direction, Tiles};
use crate::time::{gmst_rad_f64, Epoch, TimeSpan, Utc};
use crate::two_node::TwoNodeLoop;

use self::faults::{Fault, Held, Injections, Sensor};
use self::realistic::devices::{
    gauss, uniform, CoilState, Devices, Gyro, Magnetometer, Phase, Stream, SunSensor, WheelState,
};
use self::realistic::field::{albedo_cap, Magnetics, UnmodelledField};
use self::realistic::Realism;

/// Earth's gravitational parameter for the truth dynamics, m³/s².
const MU_M3_S2: f64 = 3.986_004_418e14;

/// A seeded xorshift64* generator with Gaussian samples (Box–Muller).
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator from a non-zero seed.
    pub fn new(seed: u64) -> Self {
        Self(seed.max(1))
    }
    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (x >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Standard normal.
    pub fn normal(&mut self) -> f64 {
        let u1 = self.uniform().max(1e-300);
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
    }
}

/// Sensor imperfections (1σ noise, constant bias drawn once per device).
#[derive(Clone, Debug)]
pub struct SensorNoise {
    /// Sun-sensor angle noise, rad.
    pub sun_rad: f64,
    /// Magnetometer noise per component, nT.
    pub mag_nt: f64,
    /// Magnetometer bias 1σ per component, nT.
    pub mag_bias_nt: f64,
    /// Gyro noise, rad/s.
    pub gyro_radps: f64,
    /// Gyro bias 1σ, rad/s.
    pub gyro_bias_radps: f64,
    /// Probability that one read of one device times out.
    pub dropout: f64,
}

impl SensorNoise {
    /// Perfect sensors (only the int16 quantisation remains).
    pub const IDEAL: Self = Self {
        sun_rad: 0.0,
        mag_nt: 0.0,
        mag_bias_nt: 0.0,
        gyro_radps: 0.0,
        gyro_bias_radps: 0.0,
        dropout: 0.0,
    };
}

/// Disturbance models (seed 004 defaults).
#[derive(Clone, Debug)]
pub struct Disturbances {
    /// Drag coefficient.
    pub cd: f64,
    /// Cross-section, m².
    pub area_m2: f64,
    /// Centre of pressure relative to the centre of mass, body, m.
    pub cp_body_m: Vec3d,
    /// Residual dipole, body, A·m².
    pub residual_dipole_am2: Vec3d,
    /// Solar reflectance factor q.
    pub reflectance: f64,
    /// Gravity gradient on.
    pub gravity_gradient: bool,
    /// Atmospheric density relative to the truth's drag model (1: the model's; the Monte Carlo
    /// campaigns disperse it, [`campaign::Dispersions`]).
    pub density_factor: f64,
}

impl Disturbances {
    /// Seed 004's 3U values (C_d 2.5, 1.5 × 0.1 × 0.3405 m², 72.8 mm arm, 4e-3 A·m²).
    pub fn seed004() -> Self {
        Self {
            cd: 2.5,
            area_m2: 1.5 * 0.1 * 0.3405,
            cp_body_m: Vec3d::new(0.02, 0.0, 0.07),
            residual_dipole_am2: Vec3d::new(
                4e-3 / 3f64.sqrt(),
                4e-3 / 3f64.sqrt(),
                4e-3 / 3f64.sqrt(),
            ),
            reflectance: 0.6,
            gravity_gradient: true,
            density_factor: 1.0,
        }
    }
    /// No disturbance.
    pub fn none() -> Self {
        Self {
            cd: 0.0,
            area_m2: 0.0,
            cp_body_m: Vec3d::zeros(),
            residual_dipole_am2: Vec3d::zeros(),
            reflectance: 0.0,
            gravity_gradient: false,
            density_factor: 1.0,
        }
    }
}

/// Everything the truth side needs.
#[derive(Clone, Debug)]
pub struct SimConfig {
    /// Two-line element set of the orbit (the truth's and the flight's).
    pub tle: (String, String),
    /// UTC start of the run.
    pub start: Epoch<Utc>,
    /// Body inertia, kg·m².
    pub inertia: Mat3d,
    /// Tile geometry (the same as the flight configuration's).
    pub tiles: Tiles,
    /// Magnetorquer coils: body axis, limit A·m² (the same as the flight's).
    pub coils: Vec<(Vec3d, f64)>,
    /// Wheel momentum limit, kg·m²/s.
    pub wheel_max_h_nms: f64,
    /// Each tile's wheel axis in body axes, its length the wheel's momentum scale (a wheel
    /// whose momentum is `h` along its spin axis puts `h · axis` on the body); empty: each
    /// tile's outward normal, unit length (the nominal wheels; the Monte Carlo campaigns
    /// disperse them, [`campaign::Dispersions`]).
    pub wheel_axes_body: Vec<Vec3d>,
    /// Wheel torque limit, N·m.
    pub wheel_max_torque_nm: f64,
    /// Sun-sensor field of view (half angle from the normal), rad.
    pub sun_fov_rad: f64,
    /// Sensor imperfections.
    pub noise: SensorNoise,
    /// Disturbance torques.
    pub disturbances: Disturbances,
    /// Tiles that fail, with the time (s from start).
    pub failures: Vec<(usize, f64)>,
    /// RK4 step, s.
    pub substep_s: f64,
    /// Random seed.
    pub seed: u64,
    /// The realistic truth's tables ([`realistic`]); `None`: the ideal truth (the field is IGRF
    /// itself, sensors with [`SimConfig::noise`], ideal actuators).
    pub realism: Option<Realism>,
}

/// The true state.
#[derive(Clone, Debug)]
pub struct Truth {
    /// Seconds since the start.
    pub t_s: f64,
    /// Attitude, scalar-first, reference TEME → body.
    pub q: [f64; 4],
    /// Body rate, rad/s.
    pub omega: Vec3d,
    /// Momentum of each tile's wheel along its normal, kg·m²/s.
    pub wheel_h: Vec<f64>,
}

/// The environment at one instant (truth).
#[derive(Clone, Debug)]
pub struct Environment {
    /// Position, TEME, km.
    pub r_teme_km: Vec3d,
    /// Velocity, TEME, km/s.
    pub v_teme_kmps: Vec3d,
    /// Unit Sun direction, TEME.
    pub sun_teme: Vec3d,
    /// Visible fraction of the solar disc.
    pub sun_fraction: f64,
    /// Field, TEME, nT (the truth: IGRF-14 degree 13, plus the unmodelled part in the
    /// realistic truth).
    pub b_teme_nt: Vec3d,
    /// The unmodelled part of [`Environment::b_teme_nt`], TEME, nT (zero in the ideal truth).
    pub b_unmodelled_teme_nt: Vec3d,
    /// Earth albedo as the Sun sensors see it: direction from the satellite (TEME, unit) and
    /// irradiance at normal incidence in solar units ([`realistic::field::albedo_cap`]; empty in
    /// the ideal truth).
    pub albedo_teme: Vec<(Vec3d, f64)>,
}

/// Errors of the simulator set-up.
#[derive(Debug)]
pub enum SimError {
    /// The TLE could not be read by the truth propagator.
    Tle(String),
    /// The truth orbit or a model failed at some time.
    Model(String),
}

impl std::fmt::Display for SimError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Tle(m) => write!(f, "TLE: {m}"),
            Self::Model(m) => write!(f, "model: {m}"),
        }
    }
}

/// `A(q)` of a scalar-first f64 quaternion, `v_body = A v_ref` ([`crate::attitude`]).
pub fn dcm_of(q: &[f64; 4]) -> Mat3d {
    let [q0, q1, q2, q3] = *q;
    Mat3d::new(
        q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3,
        2.0 * (q1 * q2 + q0 * q3),
        2.0 * (q1 * q3 - q0 * q2),
        2.0 * (q1 * q2 - q0 * q3),
        q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3,
        2.0 * (q2 * q3 + q0 * q1),
        2.0 * (q1 * q3 + q0 * q2),
        2.0 * (q2 * q3 - q0 * q1),
        q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3,
    )
}

fn qmul(p: &[f64; 4], r: &[f64; 4]) -> [f64; 4] {
    [
        p[0] * r[0] - p[1] * r[1] - p[2] * r[2] - p[3] * r[3],
        p[1] * r[0] + p[2] * r[3] - p[3] * r[2] + p[0] * r[1],
        -p[1] * r[3] + p[2] * r[0] + p[3] * r[1] + p[0] * r[2],
        p[1] * r[2] - p[2] * r[1] + p[3] * r[0] + p[0] * r[3],
    ]
}

/// The rotation angle between a true attitude and an f32 one, degrees.
pub fn angle_between_deg(truth: &[f64; 4], q: &Quaternion) -> f64 {
    let other = [
        f64::from(q.q0),
        f64::from(q.q1),
        f64::from(q.q2),
        f64::from(q.q3),
    ];
    let conj = [truth[0], -truth[1], -truth[2], -truth[3]];
    let d = qmul(&conj, &other);
    let v = (d[1] * d[1] + d[2] * d[2] + d[3] * d[3]).sqrt();
    2.0 * v.atan2(d[0].abs()).to_degrees()
}

/// The simulator: truth, environment and simulated tiles (cloneable: a twin continues the run
/// exactly, its random draws included).
#[derive(Clone)]
pub struct Simulator {
    config: SimConfig,
    constants: sgp4::Constants,
    epoch_offset_min: f64,
    truth: Truth,
    env: Environment,
    rng: Rng,
    mag_bias: Vec<Vec3d>,
    gyro_bias: Vec<f64>,
    wheel_cmd: Vec<f64>,
    coil_cmd: Vec<f64>,
    real: Option<Box<RealState>>,
    /// Injected faults ([`faults`]).
    faults: Injections,
}

/// What the realistic truth adds to the simulator's state ([`realistic`]).
#[derive(Clone, Debug)]
struct RealState {
    model: Realism,
    devices: Devices,
    unmodelled: UnmodelledField,
    /// Control steps completed (`advance` calls): the index of the random draws.
    step: u64,
    phase: Phase,
    /// Mean body rate over the last `advance`, rad/s (what the gyros average).
    omega_mean: Vec3d,
    /// Length of the last `advance`, s.
    last_dt_s: f64,
    /// The albedo points in body axes at this step's read instant (step, points).
    albedo_body: Option<(u64, Vec<(Vec3d, f64)>)>,
}

impl Simulator {
    /// A simulator at `config.start` with attitude `q0` and body rate `omega0`.
    pub fn new(config: SimConfig, q0: [f64; 4], omega0: Vec3d) -> Result<Self, SimError> {
        let elements =
            sgp4::Elements::from_tle(None, config.tle.0.as_bytes(), config.tle.1.as_bytes())
                .map_err(|e| SimError::Tle(e.to_string()))?;
        let constants = sgp4::Constants::from_elements_afspc_compatibility_mode(&elements)
            .map_err(|e| SimError::Tle(e.to_string()))?;
        let tle = crate::tle::Tle::parse(&config.tle.0, &config.tle.1)
            .map_err(|e| SimError::Tle(e.to_string()))?;
        let epoch_offset_min = config.start.span_since(&tle.epoch).as_seconds_f64() / 60.0;
        let mut rng = Rng::new(config.seed);
        let n = config.tiles.len();
        let mag_bias = (0..n)
            .map(|_| {
                let s = config.noise.mag_bias_nt;
                Vec3d::new(rng.normal() * s, rng.normal() * s, 0.0)
            })
            .collect();
        let gyro_bias = (0..n)
            .map(|_| rng.normal() * config.noise.gyro_bias_radps)
            .collect();
        let truth = Truth {
            t_s: 0.0,
            q: q0,
            omega: omega0,
            wheel_h: vec![0.0; n],
        };
        let coils = config.coils.len();
        let mut sim = Self {
            env: Environment {
                r_teme_km: Vec3d::zeros(),
                v_teme_kmps: Vec3d::zeros(),
                sun_teme: Vec3d::x(),
                sun_fraction: 1.0,
                b_teme_nt: Vec3d::zeros(),
                b_unmodelled_teme_nt: Vec3d::zeros(),
                albedo_teme: Vec::new(),
            },
            config,
            constants,
            epoch_offset_min,
            truth,
            rng,
            mag_bias,
            gyro_bias,
            wheel_cmd: vec![0.0; n],
            coil_cmd: vec![0.0; coils],
            real: None,
            faults: Injections::default(),
        };
        if let Some(model) = sim.config.realism.clone() {
            sim.real = Some(Box::new(sim.real_state(model, &omega0)?));
        }
        sim.env = sim.environment(0.0)?;
        Ok(sim)
    }

    /// The realistic truth's state at the start: every device's constant errors, the
    /// unmodelled field scaled on the sphere of the orbit's initial radius.
    fn real_state(&self, mut model: Realism, omega0: &Vec3d) -> Result<RealState, SimError> {
        // no wheel of the truth is faster than the ideal truth's: without its effects
        // ([`realistic::Effect::Wheel`]) the realistic wheel is the ideal one
        model.wheel.torque_limit_nm = model
            .wheel
            .torque_limit_nm
            .min(self.config.wheel_max_torque_nm);
        let seed = self.config.seed;
        let tiles = self.config.tiles.as_slice();
        let r0_m = self.environment(0.0)?.r_teme_km.norm() * 1e3;
        let unmodelled = UnmodelledField::new(&model.field, seed, r0_m);
        let per_tile =
            |has: fn(&crate::tiles::Tile) -> bool| -> Vec<bool> { tiles.iter().map(has).collect() };
        let sun = per_tile(|t| t.equipment.sun_sensor)
            .iter()
            .zip(tiles.iter())
            .enumerate()
            .map(|(i, (has, t))| has.then(|| SunSensor::new(&model.sun_sensor, t, i as u64, seed)))
            .collect();
        let magnetometer = per_tile(|t| t.equipment.magnetometer)
            .iter()
            .zip(tiles.iter())
            .enumerate()
            .map(|(i, (has, t))| {
                has.then(|| Magnetometer::new(&model.magnetometer, t, i as u64, seed))
            })
            .collect();
        let gyro: Vec<Option<Gyro>> = per_tile(|t| t.equipment.gyro)
            .iter()
            .zip(tiles.iter())
            .enumerate()
            .map(|(i, (has, t))| has.then(|| Gyro::new(&model.gyro, t, i as u64, seed)))
            .collect();
        // the Gauss–Markov biases start from their stationary distribution
        let gyro_markov_radps = (0..tiles.len())
            .map(|i| {
                model.gyro.bias_instability_radps
                    * gauss(seed, Stream::GyroMarkov, u64::MAX, i as u64)
            })
            .collect();
        let wheels = (0..tiles.len())
            .map(|_| WheelState::new(&model.wheel, self.config.wheel_max_h_nms))
            .collect();
        let coils = (0..self.config.coils.len())
            .map(|i| CoilState::new(&model.coil, i as u64, seed))
            .collect();
        let magnetics = Magnetics::new(&model.magnetics, tiles, &self.config.coils, seed);
        Ok(RealState {
            devices: Devices {
                sun,
                magnetometer,
                gyro,
                gyro_markov_radps,
                wheels,
                coils,
                magnetics,
            },
            unmodelled,
            step: 0,
            phase: Phase::Start,
            omega_mean: *omega0,
            last_dt_s: 1.0,
            albedo_body: None,
            model,
        })
    }

    /// The realistic truth's tables, if the simulator flies it.
    pub fn realism(&self) -> Option<&Realism> {
        self.real.as_ref().map(|r| &r.model)
    }

    /// The spacecraft's own fields (realistic truth only).
    pub fn magnetics(&self) -> Option<&Magnetics> {
        self.real.as_ref().map(|r| &r.devices.magnetics)
    }

    /// The unmodelled part of the field (realistic truth only).
    pub fn unmodelled_field(&self) -> Option<&UnmodelledField> {
        self.real.as_ref().map(|r| &r.unmodelled)
    }

    /// The realistic truth's per-device state (constant errors, wheels, coils).
    pub fn devices(&self) -> Option<&Devices> {
        self.real.as_ref().map(|r| &r.devices)
    }

    /// Injects `fault` from `from_s` to `until_s` (s from the start, `until_s` exclusive;
    /// `f64::INFINITY`: until [`Simulator::clear_fault`]); returns its index.
    pub fn inject(&mut self, fault: Fault, from_s: f64, until_s: f64) -> usize {
        self.faults.add(fault, from_s, until_s)
    }

    /// Ends injection `index` now.
    pub fn clear_fault(&mut self, index: usize) {
        let t = self.truth.t_s;
        self.faults.clear(index, t);
    }

    /// The injected faults.
    pub fn injections(&self) -> &Injections {
        &self.faults
    }

    /// The simulator's configuration.
    pub fn config(&self) -> &SimConfig {
        &self.config
    }

    /// The truth now.
    pub fn truth(&self) -> &Truth {
        &self.truth
    }

    /// The environment now.
    pub fn env(&self) -> &Environment {
        &self.env
    }

    /// The UTC epoch `t_s` seconds after the start.
    pub fn epoch_at(&self, t_s: f64) -> Epoch<Utc> {
        let span = TimeSpan::from_seconds_f64(t_s).unwrap_or(TimeSpan::ZERO);
        self.config.start.add(span)
    }

    fn environment(&self, t_s: f64) -> Result<Environment, SimError> {
        let p = self
            .constants
            .propagate_afspc_compatibility_mode(sgp4::MinutesSinceEpoch(
                self.epoch_offset_min + t_s / 60.0,
            ))
            .map_err(|e| SimError::Model(e.to_string()))?;
        let r = Vec3d::from(p.position);
        let v = Vec3d::from(p.velocity);
        let epoch = self.epoch_at(t_s);
        let sun = precise::sun(&epoch).map_err(|e| SimError::Model(format!("{e:?}")))?;
        let r32 = r.cast::<f32>();
        let fraction = conical(&r32, &sun)
            .map(|i| f64::from(i.fraction))
            .unwrap_or(1.0);
        let igrf = Igrf::at_epoch(&FULL, &epoch, Degree::FULL)
            .map_err(|e| SimError::Model(format!("{e:?}")))?;
        let ut1 = epoch
            .to_ut1(None)
            .map_err(|e| SimError::Model(format!("{e:?}")))?;
        let gmst = gmst_rad_f64(&ut1) as f32;
        let b = igrf
            .teme(&r32, gmst)
            .map_err(|e| SimError::Model(format!("{e:?}")))?;
        let sun_teme = sun.direction.cast::<f64>().normalize();
        let (b_unmodelled, albedo) = match &self.real {
            None => (Vec3d::zeros(), Vec::new()),
            Some(real) => {
                // Earth-fixed = R3(θ) TEME, with the f64 sidereal angle
                let (s, c) = gmst_rad_f64(&ut1).sin_cos();
                let r_m = r * 1e3;
                let r_ecef = Vec3d::new(c * r_m.x + s * r_m.y, c * r_m.y - s * r_m.x, r_m.z);
                let d = real.unmodelled.ecef_nt(&r_ecef);
                let d_teme = Vec3d::new(c * d.x - s * d.y, s * d.x + c * d.y, d.z);
                let albedo = albedo_cap(&r, &sun_teme, real.model.sun_sensor.albedo, 6, 12);
                (d_teme, albedo)
            }
        };
        Ok(Environment {
            r_teme_km: r,
            v_teme_kmps: v,
            sun_teme,
            sun_fraction: fraction,
            b_teme_nt: b.cast::<f64>() + b_unmodelled,
            b_unmodelled_teme_nt: b_unmodelled,
            albedo_teme: albedo,
        })
    }

    /// The coils' dipole as commanded (the ideal truth's coils), body, A·m².
    fn commanded_dipole(&self) -> Vec3d {
        self.config
            .coils
            .iter()
            .zip(self.coil_cmd.iter())
            .fold(Vec3d::zeros(), |acc, ((axis, _), m)| acc + axis * *m)
    }

    /// The dipole coil `coil` gives now (its read-back, [`TileBus::read_coil_dipole`]), A·m²:
    /// the ideal truth's commanded (or forced) dipole, the realistic coil's present dipole
    /// ([`realistic::CoilModel`]: quantisation, scale factor, rise and decay). `None`: no such
    /// coil.
    pub fn coil_dipole_am2(&self, coil: usize) -> Option<f64> {
        match &self.real {
            None => self.coil_cmd.get(coil).copied(),
            Some(real) => real.devices.coils.get(coil).map(|c| c.m_am2),
        }
    }

    /// Density at 500 km of the drag model, kg/m³: seed 004's worst case in the ideal truth,
    /// the stated solar activity's in the realistic truth.
    fn density_500km(&self) -> f64 {
        self.real
            .as_ref()
            .map_or(4.38e-12, |r| r.model.solar_activity.density_500km())
            * self.config.disturbances.density_factor
    }

    /// The external torque on the body now (magnetic + disturbances), N·m, body axes, with the
    /// coils' dipole `dipole` (body, A·m²).
    fn external_torque(&self, q: &[f64; 4], dipole: &Vec3d, rho_500km: f64) -> Vec3d {
        let a = dcm_of(q);
        let b_body_t = a * self.env.b_teme_nt * 1e-9;
        let d = &self.config.disturbances;
        let mut tau = (dipole + d.residual_dipole_am2).cross(&b_body_t);
        let r_m = self.env.r_teme_km * 1e3;
        let r = r_m.norm();
        if d.gravity_gradient {
            let nadir_body = a * (-r_m / r);
            let i = &self.config.inertia;
            tau += 3.0 * MU_M3_S2 / (r * r * r) * nadir_body.cross(&(i * nadir_body));
        }
        if d.area_m2 > 0.0 {
            // exponential atmosphere (scale height 60 km, 4.4e-12 kg/m³ at 500 km: seed 004)
            let h_km = r / 1e3 - 6378.137;
            let rho = rho_500km * ((500.0 - h_km) / 60.0).exp();
            let v_body = a * (self.env.v_teme_kmps * 1e3);
            let v = v_body.norm();
            if v > 0.0 {
                let force = -v_body / v * (0.5 * rho * d.cd * d.area_m2 * v * v);
                tau += d.cp_body_m.cross(&force);
            }
            if self.env.sun_fraction > 0.0 {
                let s_body = a * self.env.sun_teme;
                let force =
                    -s_body * (4.56e-6 * d.area_m2 * (1.0 + d.reflectance) * self.env.sun_fraction);
                tau += d.cp_body_m.cross(&force);
            }
        }
        tau
    }

    /// Each tile's wheel axis in body axes, scaled by the wheel's momentum scale
    /// ([`SimConfig::wheel_axes_body`]).
    pub fn wheel_axes_body(&self) -> Vec<Vec3d> {
        if self.config.wheel_axes_body.len() == self.config.tiles.len() {
            self.config.wheel_axes_body.clone()
        } else {
            self.config
                .tiles
                .iter()
                .map(|t| t.normal_body().cast::<f64>())
                .collect()
        }
    }

    /// The tiles' wheel axes (body) and whether each tile has a wheel.
    fn wheel_axes(&self) -> (Vec<Vec3d>, Vec<bool>) {
        let axes = self.wheel_axes_body();
        let ok = self
            .config
            .tiles
            .iter()
            .map(|t| t.equipment.reaction_wheel)
            .collect();
        (axes, ok)
    }

    /// One RK4 step of `h` seconds of the rigid body with the wheels' momentum changing at
    /// `hdot` (kg·m²/s², per tile) and the coils' dipole `dipole` (body) held.
    fn rk4_substep(&mut self, h: f64, axes: &[Vec3d], hdot: &[f64], dipole: &Vec3d, rho: f64) {
        let i = self.config.inertia;
        let inv = i.try_inverse().unwrap_or_else(Mat3d::identity);
        let hdot_body: Vec3d = axes
            .iter()
            .zip(hdot.iter())
            .fold(Vec3d::zeros(), |a, (z, d)| a + z * *d);
        let deriv = |q: &[f64; 4], w: &Vec3d, hw: &[f64], sim: &Self| {
            let h_body: Vec3d = axes
                .iter()
                .zip(hw.iter())
                .fold(Vec3d::zeros(), |a, (z, x)| a + z * *x);
            let tau = sim.external_torque(q, dipole, rho);
            let wdot = inv * (tau - w.cross(&(i * w + h_body)) - hdot_body);
            let qd = qmul(q, &[0.0, w.x, w.y, w.z]);
            ([0.5 * qd[0], 0.5 * qd[1], 0.5 * qd[2], 0.5 * qd[3]], wdot)
        };
        let q0 = self.truth.q;
        let w0 = self.truth.omega;
        let hw0 = self.truth.wheel_h.clone();
        let hw_at = |k: f64| -> Vec<f64> {
            hw0.iter()
                .zip(hdot.iter())
                .map(|(x, d)| x + d * k)
                .collect()
        };
        let add = |q: &[f64; 4], d: &[f64; 4], k: f64| {
            [
                q[0] + k * d[0],
                q[1] + k * d[1],
                q[2] + k * d[2],
                q[3] + k * d[3],
            ]
        };
        let (k1q, k1w) = deriv(&q0, &w0, &hw0, self);
        let (k2q, k2w) = deriv(
            &add(&q0, &k1q, 0.5 * h),
            &(w0 + k1w * 0.5 * h),
            &hw_at(0.5 * h),
            self,
        );
        let (k3q, k3w) = deriv(
            &add(&q0, &k2q, 0.5 * h),
            &(w0 + k2w * 0.5 * h),
            &hw_at(0.5 * h),
            self,
        );
        let (k4q, k4w) = deriv(&add(&q0, &k3q, h), &(w0 + k3w * h), &hw_at(h), self);
        let mut q = [0.0; 4];
        for (k, qk) in q.iter_mut().enumerate() {
            *qk = q0[k] + h / 6.0 * (k1q[k] + 2.0 * k2q[k] + 2.0 * k3q[k] + k4q[k]);
        }
        let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
        self.truth.q = [q[0] / n, q[1] / n, q[2] / n, q[3] / n];
        self.truth.omega = w0 + (k1w + k2w * 2.0 + k3w * 2.0 + k4w) * (h / 6.0);
        self.truth.wheel_h = hw_at(h);
        self.truth.t_s += h;
    }

    /// Advances the truth by `dt_s` with the actuator commands in force (in the realistic
    /// truth: those of this step from its actuation instant, [`realistic::StepTiming`]).
    pub fn advance(&mut self, dt_s: f64) -> Result<(), SimError> {
        self.apply_forced_faults();
        if self.real.is_some() {
            return self.advance_realistic(dt_s);
        }
        let steps = (dt_s / self.config.substep_s).ceil().max(1.0) as usize;
        let h = dt_s / steps as f64;
        let (axes, wheel_ok) = self.wheel_axes();
        let rho = self.density_500km();
        for _ in 0..steps {
            // wheel torques this substep: slew toward the command at the torque limit
            let hdot: Vec<f64> = self
                .truth
                .wheel_h
                .iter()
                .zip(self.wheel_cmd.iter())
                .zip(wheel_ok.iter())
                .map(|((hw, cmd), ok)| {
                    if !ok {
                        return 0.0;
                    }
                    ((cmd - hw) / h).clamp(
                        -self.config.wheel_max_torque_nm,
                        self.config.wheel_max_torque_nm,
                    )
                })
                .collect();
            let dipole = self.commanded_dipole();
            self.rk4_substep(h, &axes, &hdot, &dipole, rho);
        }
        self.env = self.environment(self.truth.t_s)?;
        Ok(())
    }

    /// [`Simulator::advance`] in the realistic truth: the step's commands take effect at its
    /// actuation instant; wheels and coils follow their own dynamics ([`realistic::devices`]);
    /// the gyros' averages and Gauss–Markov biases move on.
    fn advance_realistic(&mut self, dt_s: f64) -> Result<(), SimError> {
        let Some(mut real) = self.real.take() else {
            return Ok(());
        };
        // the step ends at t + dt: the substeps of its two segments (before and after the
        // actuation instant) sum to dt only to rounding, which after a few hundred steps put
        // the step times just under the whole seconds (299.999 999 999 9 s)
        let t_end = self.truth.t_s + dt_s;
        let (axes, wheel_ok) = self.wheel_axes();
        let rho = self.density_500km();
        let pending = real.devices.wheels.iter().any(|w| w.pending_nms.is_some())
            || real.devices.coils.iter().any(|c| c.pending_am2.is_some());
        let split = if pending {
            real.model.timing.actuate_s.clamp(0.0, dt_s)
        } else {
            dt_s
        };
        let apply = |real: &mut RealState| {
            for w in &mut real.devices.wheels {
                if let Some(h) = w.pending_nms.take() {
                    w.setpoint_nms = h;
                }
            }
            for c in &mut real.devices.coils {
                if let Some(m) = c.pending_am2.take() {
                    c.target_am2 = m;
                }
            }
        };
        let mut omega_integral = Vec3d::zeros();
        for (segment, apply_first) in [(split, false), (dt_s - split, true)] {
            if apply_first {
                apply(&mut real);
            }
            if segment <= 0.0 {
                continue;
            }
            let steps = (segment / self.config.substep_s).ceil().max(1.0) as usize;
            let h = segment / steps as f64;
            for _ in 0..steps {
                let model = &real.model;
                let hdot: Vec<f64> = real
                    .devices
                    .wheels
                    .iter_mut()
                    .zip(wheel_ok.iter())
                    .map(|(w, ok)| {
                        if *ok {
                            w.advance(&model.wheel, h) / h
                        } else {
                            0.0
                        }
                    })
                    .collect();
                let dipole = real
                    .devices
                    .coils
                    .iter_mut()
                    .zip(self.config.coils.iter())
                    .fold(Vec3d::zeros(), |acc, (c, (axis, _))| {
                        acc + axis * c.advance(&model.coil, h)
                    });
                let w0 = self.truth.omega;
                self.rk4_substep(h, &axes, &hdot, &dipole, rho);
                for (t, w) in self
                    .truth
                    .wheel_h
                    .iter_mut()
                    .zip(real.devices.wheels.iter())
                {
                    *t = w.h_nms;
                }
                omega_integral += (w0 + self.truth.omega) * (0.5 * h);
            }
        }
        apply(&mut real);
        if dt_s > 0.0 {
            real.omega_mean = omega_integral / dt_s;
            real.last_dt_s = dt_s;
        }
        // the gyros' bias instability: first-order Gauss–Markov over the step
        let g = &real.model.gyro;
        if g.bias_correlation_s > 0.0 {
            let decay = (-dt_s / g.bias_correlation_s).exp();
            let kick = g.bias_instability_radps * (1.0 - decay * decay).max(0.0).sqrt();
            for (k, b) in real.devices.gyro_markov_radps.iter_mut().enumerate() {
                *b = *b * decay
                    + kick * gauss(self.config.seed, Stream::GyroMarkov, real.step, k as u64);
            }
        }
        real.step += 1;
        real.phase = Phase::Start;
        self.real = Some(real);
        self.truth.t_s = t_end;
        self.env = self.environment(self.truth.t_s)?;
        Ok(())
    }

    /// Stopped wheels and coils forced open or on take their state whatever was commanded.
    fn apply_forced_faults(&mut self) {
        let t = self.truth.t_s;
        for (tile, cmd) in self.wheel_cmd.iter_mut().enumerate() {
            if self.faults.wheel_stopped(t, tile) {
                *cmd = 0.0;
                if let Some(w) = self
                    .real
                    .as_mut()
                    .and_then(|r| r.devices.wheels.get_mut(tile))
                {
                    w.setpoint_nms = 0.0;
                    w.pending_nms = None;
                }
            }
        }
        for (coil, cmd) in self.coil_cmd.iter_mut().enumerate() {
            if let Some(m) = self.faults.coil_forced(t, coil) {
                *cmd = m;
                if let Some(real) = self.real.as_mut() {
                    let model = &real.model.coil;
                    if let Some(c) = real.devices.coils.get_mut(coil) {
                        c.target_am2 = c.target_of(model, m);
                        c.pending_am2 = None;
                    }
                }
            }
        }
    }

    fn failed(&self, tile: usize) -> bool {
        self.config
            .failures
            .iter()
            .any(|(i, t)| *i == tile && self.truth.t_s >= *t)
    }

    fn dropout(&mut self) -> bool {
        self.config.noise.dropout > 0.0 && self.rng.uniform() < self.config.noise.dropout
    }

    fn tile_check(&mut self, tile: usize) -> Result<(), ErrorKind> {
        if tile >= self.config.tiles.len() || self.failed(tile) {
            return Err(ErrorKind::DeviceAbsent);
        }
        if self.dropout() {
            return Err(ErrorKind::Timeout);
        }
        Ok(())
    }

    fn tile_matrix(&self, tile: usize) -> Mat3d {
        self.config
            .tiles
            .get(tile)
            .map_or_else(Mat3d::identity, |t| t.body_to_tile.matrix().cast::<f64>())
    }

    /// The momentum tile `tile`'s wheel reports, kg·m²/s: in the realistic truth its
    /// tachometer (whole rpm, [`realistic::WheelModel`]), in the ideal truth the true momentum.
    ///
    /// The simulator side of the HAL's wheel read-back ([`TileBus::read_wheel_momentum`],
    /// which also fails it in a bus burst or on a dead tile, and gives it as a word). It draws
    /// no random number: the ideal truth's runs stay bit for bit what they were, and in the
    /// realistic truth its time-outs are a pure function of the seed, step and tile (at the
    /// scenario's dropout rate).
    pub fn wheel_momentum_nms(&mut self, tile: usize) -> Result<f32, ErrorKind> {
        let has_wheel = self
            .config
            .tiles
            .get(tile)
            .is_some_and(|t| t.equipment.reaction_wheel);
        if !has_wheel || self.failed(tile) {
            return Err(ErrorKind::DeviceAbsent);
        }
        match &self.real {
            None => Ok(self.truth.wheel_h.get(tile).copied().unwrap_or(0.0) as f32),
            Some(real) => {
                if self.real_dropout(tile, 3) {
                    return Err(ErrorKind::Timeout);
                }
                let model = &real.model.wheel;
                Ok(real
                    .devices
                    .wheels
                    .get(tile)
                    .map_or(0.0, |w| w.readback_nms(model)) as f32)
            }
        }
    }

    /// A realistic read's time-out: a pure function of the seed, the step, the tile and the
    /// device (0 Sun, 1 magnetometer, 2 gyro, 3 wheel).
    fn real_dropout(&self, tile: usize, device: u64) -> bool {
        let p = self.config.noise.dropout;
        let step = self.real.as_ref().map_or(0, |r| r.step);
        p > 0.0
            && uniform(
                self.config.seed,
                Stream::Dropout,
                step,
                4 * tile as u64 + device,
            ) < p
    }

    /// The realistic truth's checks before a read: the tile fails or times out, has the device;
    /// the step moves to its read phase.
    fn real_check(&mut self, tile: usize, device: u64) -> Result<(), ErrorKind> {
        if tile >= self.config.tiles.len() || self.failed(tile) {
            return Err(ErrorKind::DeviceAbsent);
        }
        if self.real_dropout(tile, device) {
            return Err(ErrorKind::Timeout);
        }
        if let Some(real) = self.real.as_mut() {
            if real.phase == Phase::Start {
                real.phase = Phase::Read;
            }
        }
        Ok(())
    }

    /// The attitude (scalar-first) at this step's read instant: the truth now turned by the
    /// body rate over the read latency.
    fn q_at_read(&self) -> [f64; 4] {
        let latency = self.real.as_ref().map_or(0.0, |r| r.model.timing.read_s);
        let w = self.truth.omega;
        let angle = w.norm() * latency;
        if angle < 1e-15 {
            return self.truth.q;
        }
        let axis = w.normalize();
        let (s, c) = (0.5 * angle).sin_cos();
        qmul(&self.truth.q, &[c, s * axis.x, s * axis.y, s * axis.z])
    }

    fn real_read_sun(&mut self, tile: usize) -> Result<Option<[i16; 2]>, ErrorKind> {
        self.real_check(tile, 0)?;
        let a_read = dcm_of(&self.q_at_read());
        let sun_body = a_read * self.env.sun_teme;
        let fraction = self.env.sun_fraction;
        let seed = self.config.seed;
        let Some(real) = self.real.as_mut() else {
            return Err(ErrorKind::Other);
        };
        let step = real.step;
        if real.albedo_body.as_ref().map(|(k, _)| *k) != Some(step) {
            let points = self
                .env
                .albedo_teme
                .iter()
                .map(|(d, w)| (a_read * d, *w))
                .collect();
            real.albedo_body = Some((step, points));
        }
        let Some(Some(sensor)) = real.devices.sun.get(tile) else {
            return Err(ErrorKind::DeviceAbsent);
        };
        let albedo = real.albedo_body.as_ref().map_or(&[][..], |(_, p)| &p[..]);
        let noise = (
            gauss(seed, Stream::SunNoise, step, 2 * tile as u64),
            gauss(seed, Stream::SunNoise, step, 2 * tile as u64 + 1),
        );
        let reading = sensor.read(&real.model.sun_sensor, &sun_body, fraction, albedo, noise);
        let t = self.truth.t_s;
        match reading {
            None => Ok(None),
            Some((a, b)) => {
                let a = self.faults.poison(t, tile, Sensor::Sun, a);
                let b = self.faults.poison(t, tile, Sensor::Sun, b);
                Ok(Some([quantise(a, 1e-4)?, quantise(b, 1e-4)?]))
            }
        }
    }

    /// The field (body, nT) tile `tile`'s magnetometer sees at this step's read instant: the
    /// truth field and, if the model says so, the spacecraft's own.
    pub fn field_at_magnetometer_nt(&self, tile: usize) -> Vec3d {
        let b = dcm_of(&self.q_at_read()) * self.env.b_teme_nt;
        let Some(real) = self.real.as_ref() else {
            return b;
        };
        if !real.model.magnetometer.contamination {
            return b;
        }
        let latency = real.model.timing.read_s;
        let m = &real.model.magnetics;
        let turns_area = m.coil_turns * m.coil_side_m * m.coil_side_m;
        let coil_a: Vec<f64> = real
            .devices
            .coils
            .iter()
            .map(|c| {
                if turns_area > 0.0 {
                    c.at(&real.model.coil, latency) / turns_area
                } else {
                    0.0
                }
            })
            .collect();
        let rotor: Vec<f64> = real
            .devices
            .wheels
            .iter()
            .map(|w| w.angle_rad + w.h_nms / w.inertia_kgm2 * latency)
            .collect();
        b + real
            .devices
            .magnetics
            .at_magnetometer_nt(tile, &coil_a, &rotor)
    }

    fn real_read_magnetometer(&mut self, tile: usize) -> Result<[i16; 2], ErrorKind> {
        self.real_check(tile, 1)?;
        let b = self.field_at_magnetometer_nt(tile);
        let seed = self.config.seed;
        let Some(real) = self.real.as_ref() else {
            return Err(ErrorKind::Other);
        };
        let Some(Some(sensor)) = real.devices.magnetometer.get(tile) else {
            return Err(ErrorKind::DeviceAbsent);
        };
        let noise = (
            gauss(seed, Stream::MagNoise, real.step, 2 * tile as u64),
            gauss(seed, Stream::MagNoise, real.step, 2 * tile as u64 + 1),
        );
        let model = &real.model.magnetometer;
        let [x, y] = sensor.read(model, &b, noise);
        let t = self.truth.t_s;
        let x = self.faults.poison(t, tile, Sensor::Magnetometer, x);
        let y = self.faults.poison(t, tile, Sensor::Magnetometer, y);
        if x.is_nan() || y.is_nan() || x.abs() > model.range_nt || y.abs() > model.range_nt {
            return Err(ErrorKind::OutOfRange);
        }
        Ok([quantise(x, 10.0)?, quantise(y, 10.0)?])
    }

    fn real_read_gyro(&mut self, tile: usize) -> Result<i16, ErrorKind> {
        self.real_check(tile, 2)?;
        let seed = self.config.seed;
        let Some(real) = self.real.as_ref() else {
            return Err(ErrorKind::Other);
        };
        let Some(Some(gyro)) = real.devices.gyro.get(tile) else {
            return Err(ErrorKind::DeviceAbsent);
        };
        let model = &real.model.gyro;
        let sigma = model.arw_rad_per_sqrt_s / real.last_dt_s.max(1e-6).sqrt();
        let markov = real
            .devices
            .gyro_markov_radps
            .get(tile)
            .copied()
            .unwrap_or(0.0);
        let omega = if real.model.timing.gyro_period_mean {
            &real.omega_mean
        } else {
            &self.truth.omega
        };
        let w = gyro.axis_body.dot(omega)
            + gyro.bias_radps
            + markov
            + sigma * gauss(seed, Stream::GyroNoise, real.step, tile as u64);
        let w = self.faults.poison(self.truth.t_s, tile, Sensor::Gyro, w);
        if w.is_nan() || w.abs() > model.range_radps {
            return Err(ErrorKind::OutOfRange);
        }
        quantise(w, 1e-4)
    }

    /// A realistic actuator command: at once before any read of the step (the loop's
    /// coils-off), else at the step's actuation instant.
    fn real_command(&mut self, wheel: Option<(usize, f64)>, coil: Option<(usize, f64)>) {
        let Some(real) = self.real.as_mut() else {
            return;
        };
        let now = real.phase == Phase::Start;
        if !now {
            real.phase = Phase::Actuate;
        }
        if let Some((tile, h)) = wheel {
            let model = &real.model.wheel;
            if let Some(w) = real.devices.wheels.get_mut(tile) {
                let q = w.quantised(model, h);
                if now {
                    w.setpoint_nms = q;
                } else {
                    w.pending_nms = Some(q);
                }
            }
        }
        if let Some((index, m)) = coil {
            let model = &real.model.coil;
            if let Some(c) = real.devices.coils.get_mut(index) {
                let target = c.target_of(model, m);
                if now {
                    c.target_am2 = target;
                } else {
                    c.pending_am2 = Some(target);
                }
            }
        }
    }
}

/// Rounds to an int16 count, or `OutOfRange`.
fn quantise(value: f64, lsb: f64) -> Result<i16, ErrorKind> {
    let counts = (value / lsb).round();
    if !counts.is_finite() || counts <= f64::from(i16::MIN) || counts >= f64::from(i16::MAX) {
        Err(ErrorKind::OutOfRange)
    } else {
        Ok(counts as i16)
    }
}

impl Simulator {
    /// Before a read: a bus burst or a dead tile fails it (the step moves to its read phase).
    fn fault_gate(&mut self, tile: usize) -> Result<(), ErrorKind> {
        match self.faults.tile_error(self.truth.t_s, tile) {
            Some(e) => {
                if let Some(real) = self.real.as_mut() {
                    if real.phase == Phase::Start {
                        real.phase = Phase::Read;
                    }
                }
                Err(e)
            }
            None => Ok(()),
        }
    }

    fn read_sun_device(&mut self, tile: usize) -> Result<Option<[i16; 2]>, ErrorKind> {
        if self.real.is_some() {
            return self.real_read_sun(tile);
        }
        self.tile_check(tile)?;
        if self.env.sun_fraction < 0.5 {
            return Ok(None);
        }
        let s_tile = self.tile_matrix(tile) * dcm_of(&self.truth.q) * self.env.sun_teme;
        if s_tile.z < self.config.sun_fov_rad.cos() {
            return Ok(None);
        }
        let angles = sun_angles_of_direction(&s_tile.cast::<f32>());
        let sigma = self.config.noise.sun_rad;
        let a = f64::from(angles.a_rad) + self.rng.normal() * sigma;
        let b = f64::from(angles.b_rad) + self.rng.normal() * sigma;
        let t = self.truth.t_s;
        let a = self.faults.poison(t, tile, Sensor::Sun, a);
        let b = self.faults.poison(t, tile, Sensor::Sun, b);
        Ok(Some([quantise(a, 1e-4)?, quantise(b, 1e-4)?]))
    }

    fn read_magnetometer_device(&mut self, tile: usize) -> Result<[i16; 2], ErrorKind> {
        if self.real.is_some() {
            return self.real_read_magnetometer(tile);
        }
        self.tile_check(tile)?;
        let b_tile = self.tile_matrix(tile) * dcm_of(&self.truth.q) * self.env.b_teme_nt;
        let bias = self
            .mag_bias
            .get(tile)
            .copied()
            .unwrap_or_else(Vec3d::zeros);
        let sigma = self.config.noise.mag_nt;
        let x = b_tile.x + bias.x + self.rng.normal() * sigma;
        let y = b_tile.y + bias.y + self.rng.normal() * sigma;
        let t = self.truth.t_s;
        let x = self.faults.poison(t, tile, Sensor::Magnetometer, x);
        let y = self.faults.poison(t, tile, Sensor::Magnetometer, y);
        Ok([quantise(x, 10.0)?, quantise(y, 10.0)?])
    }

    fn read_gyro_device(&mut self, tile: usize) -> Result<i16, ErrorKind> {
        if self.real.is_some() {
            return self.real_read_gyro(tile);
        }
        self.tile_check(tile)?;
        let z = self.tile_matrix(tile).row(2).transpose();
        let bias = self.gyro_bias.get(tile).copied().unwrap_or(0.0);
        let w = z.dot(&self.truth.omega) + bias + self.rng.normal() * self.config.noise.gyro_radps;
        quantise(
            self.faults.poison(self.truth.t_s, tile, Sensor::Gyro, w),
            1e-4,
        )
    }
}

impl TileBus for Simulator {
    fn read_sun(&mut self, tile: usize) -> Result<Option<[i16; 2]>, ErrorKind> {
        self.fault_gate(tile)?;
        let t = self.truth.t_s;
        let reading = self.read_sun_device(tile);
        let reading = if self.faults.dark(t) {
            reading.map(|_| None)
        } else {
            reading
        };
        match self
            .faults
            .replace(t, tile, Sensor::Sun, Held::Sun(reading?))
        {
            Held::Sun(r) => Ok(r),
            _ => Err(ErrorKind::Other),
        }
    }

    fn read_magnetometer(&mut self, tile: usize) -> Result<[i16; 2], ErrorKind> {
        self.fault_gate(tile)?;
        let t = self.truth.t_s;
        let reading = self.read_magnetometer_device(tile)?;
        match self
            .faults
            .replace(t, tile, Sensor::Magnetometer, Held::Magnetometer(reading))
        {
            Held::Magnetometer(r) => Ok(r),
            _ => Err(ErrorKind::Other),
        }
    }

    fn read_gyro(&mut self, tile: usize) -> Result<i16, ErrorKind> {
        self.fault_gate(tile)?;
        let t = self.truth.t_s;
        let reading = self.read_gyro_device(tile)?;
        match self
            .faults
            .replace(t, tile, Sensor::Gyro, Held::Gyro(reading))
        {
            Held::Gyro(r) => Ok(r),
            _ => Err(ErrorKind::Other),
        }
    }

    fn set_wheel_momentum(&mut self, tile: usize, h_nms: f32) -> Result<(), ErrorKind> {
        if tile >= self.wheel_cmd.len() || self.failed(tile) {
            return Err(ErrorKind::DeviceAbsent);
        }
        let h = f64::from(h_nms);
        // the drive refuses anything past its limit, compared as it receives it (f32)
        if !h_nms.is_finite() || h_nms.abs() > self.config.wheel_max_h_nms as f32 {
            return Err(ErrorKind::OutOfRange);
        }
        let h = self.faults.wheel(self.truth.t_s, tile, h)?;
        if let Some(c) = self.wheel_cmd.get_mut(tile) {
            *c = h;
        }
        self.real_command(Some((tile, h)), None);
        Ok(())
    }

    fn set_dipole(&mut self, coil: usize, m_am2: f32) -> Result<(), ErrorKind> {
        let limit = self
            .config
            .coils
            .get(coil)
            .map(|c| c.1)
            .ok_or(ErrorKind::DeviceAbsent)?;
        let m = f64::from(m_am2);
        let t = self.truth.t_s;
        if !m_am2.is_finite() || m_am2.abs() > limit as f32 {
            // the driver switches the coil off (unless the bus or the coil itself fails)
            let off = self.faults.coil(t, coil, 0.0)?;
            if let Some(c) = self.coil_cmd.get_mut(coil) {
                *c = off;
            }
            self.real_command(None, Some((coil, off)));
            return Err(ErrorKind::OutOfRange);
        }
        let m = self.faults.coil(t, coil, m)?;
        if let Some(c) = self.coil_cmd.get_mut(coil) {
            *c = m;
        }
        self.real_command(None, Some((coil, m)));
        Ok(())
    }

    /// Returns at once: the truth places the reads and the commands in the step itself
    /// ([`realistic::StepTiming`], which includes this wait for the two nodes).
    fn read_wheel_momentum(&mut self, tile: usize) -> Result<Option<i16>, ErrorKind> {
        self.fault_gate(tile)?;
        let h = self.wheel_momentum_nms(tile)?;
        quantise(f64::from(h), f64::from(crate::tiles::WHEEL_LSB_NMS)).map(Some)
    }

    /// The coils' current sense is the attitude node's own (not on the tile bus): no time-out;
    /// a bus burst fails it as it fails the coils' commands ([`faults::Injections::bus_burst`]).
    fn read_coil_dipole(&mut self, coil: usize) -> Result<Option<i16>, ErrorKind> {
        if self.faults.bus_burst(self.truth.t_s) {
            return Err(ErrorKind::Bus);
        }
        let m = self.coil_dipole_am2(coil).ok_or(ErrorKind::DeviceAbsent)?;
        quantise(m, f64::from(crate::tiles::COIL_LSB_AM2)).map(Some)
    }

    fn delay_us(&mut self, _: u32) {}
}

/// One logged sample of a run.
#[derive(Clone, Debug)]
pub struct Sample {
    /// Seconds since the start.
    pub t_s: f64,
    /// Mode after the step.
    pub mode: Mode,
    /// True body rate, rad/s.
    pub omega_true: Vec3d,
    /// True attitude error to the target, degrees (None without a target).
    pub pointing_error_deg: Option<f64>,
    /// Error of the loop's filtered attitude against the truth, degrees.
    pub estimate_error_deg: Option<f64>,
    /// True wheel momentum (body), kg·m²/s.
    pub h_wheels_body: Vec3d,
    /// Commanded dipole, A·m².
    pub dipole_am2: Vec3,
    /// Visible fraction of the solar disc.
    pub sun_fraction: f64,
    /// Any fault flag.
    pub report: StepReport,
}

impl Sample {
    /// The sample of the step just taken at `t` (s): the truth now, the loop's `report`, and the
    /// pointing error against `target` (reference → body, scalar-first), if any.
    pub fn of_step(sim: &Simulator, t: f64, report: StepReport, target: Option<[f64; 4]>) -> Self {
        let truth = sim.truth();
        let h_body = sim
            .wheel_axes_body()
            .into_iter()
            .zip(truth.wheel_h.iter())
            .fold(Vec3d::zeros(), |a, (z, h)| a + z * *h);
        let pointing_error_deg = target.map(|q| {
            let q32 = Quaternion {
                q0: q[0] as f32,
                q1: q[1] as f32,
                q2: q[2] as f32,
                q3: q[3] as f32,
            };
            angle_between_deg(&truth.q, &q32)
        });
        Sample {
            t_s: t,
            mode: report.mode,
            omega_true: truth.omega,
            pointing_error_deg,
            estimate_error_deg: report.attitude.map(|q| angle_between_deg(&truth.q, &q)),
            h_wheels_body: h_body,
            dipole_am2: report.dipole_body_am2,
            sun_fraction: sim.env().sun_fraction,
            report,
        }
    }
}

/// Runs the loop against the simulator for `duration_s` at `dt_s`, applying `commands` (time
/// in s from the start) and measuring the pointing error against `target(t)`.
pub fn run<const N: usize, const F: usize>(
    sim: &mut Simulator,
    acs: &mut TwoNodeLoop<'_, N, F>,
    duration_s: f64,
    dt_s: f64,
    commands: &[(f64, Command)],
    target: impl Fn(f64) -> Option<[f64; 4]>,
) -> Result<Vec<Sample>, SimError> {
    let steps = (duration_s / dt_s).round() as usize;
    let mut out = Vec::with_capacity(steps);
    let mut pending: Vec<(f64, Command)> = commands.to_vec();
    let mut last_attitude: Option<Quaternion> = None;
    for _ in 0..steps {
        let t = sim.truth().t_s;
        let now = sim.epoch_at(t);
        let mut k = 0;
        while k < pending.len() {
            if pending[k].0 <= t {
                let (_, c) = pending.remove(k);
                let _ = acs.command(c, last_attitude.as_ref(), now);
            } else {
                k += 1;
            }
        }
        let report = acs.step(sim, now, dt_s as f32);
        last_attitude = report.attitude;
        out.push(Sample::of_step(sim, t, report, target(t)));
        sim.advance(dt_s)?;
    }
    Ok(out)
}
