//! Built-in closed-loop scenarios: detumbling, sun-safe acquisition through a whole eclipse,
//! tracking with wheels (on a dawn-dusk orbit, and through the longest eclipses), a failed tile,
//! a slew (all flying the flight configuration), and the
//! thesis slew of seed 000 ch. 12 (the thesis's own satellite).
//!
//! Each scenario is plain data: the satellite the loop flies, the truth configuration, the
//! initial state, the ground commands and the target attitude the pointing error is measured
//! against. Every constructor gives the realistic truth ([`super::realistic`]);
//! [`Scenario::with_truth`] switches to the ideal truth, which for the thesis scenarios is the
//! thesis's own noise model (ideal sensors, or about 1 % noise: `acs demo` compares with the
//! thesis's figures in it). [`Scenario::run`] builds the loop, [`Scenario::orbit`] its element set,
//! [`Scenario::simulator`] the truth, and [`Scenario::fly`] flies any loop over the scenario's
//! configuration (the pieces another way of running the loop, e.g. on the target, reuses).
//!
//! # What flies
//! `detumble`, `sun-safe`, `tracking`, `tracking-eclipse`, `failed-tile` and `slew` fly
//! [`crate::flight::CONFIG`] through
//! [`FlightLoop`], the two flight images' nodes composed ([`Satellite::Flight`]): the nodes borrow the
//! constant itself, not a copy, and the truth's spacecraft (inertia, tile geometry and
//! equipment, coils and their limits, wheel momentum limit) is built from the same constant
//! ([`spacecraft`]), so what `acs sim` flies cannot diverge from what flies.
//!
//! What the constant does not carry comes from elsewhere and is the same for these six:
//!
//! | truth item | value | source |
//! |---|---|---|
//! | orbit, field, Sun, sensors | the simulator's own f64 orbit, IGRF-14 at degree 13, precise Sun, sensor models | [`super`] |
//! | truth | realistic ([`super::realistic::Realism::DEFAULT`]) unless [`Scenario::with_truth`] says ideal | issue #18 |
//! | wheel torque limit (ideal truth) | 1e-3 N·m | issue #8's scenarios (unchanged; the realistic truth has its wheel class's) |
//! | Sun-sensor field of view (ideal truth) | 80° half angle | issue #8's scenarios (unchanged; the realistic truth has its sensor class's) |
//! | sensor noise (ideal truth) | per scenario ([`SensorNoise`]) | issue #8's scenarios (unchanged; the realistic truth has its device tables) |
//! | disturbances | `C_d` 2.5, 0.051 m², centre of pressure (20, 0, 70) mm, residual dipole 4e-3 A·m², gravity gradient, `q` 0.6 | seed 004 §2.1 ([`Disturbances::seed004`]) |
//!
//! The disturbances: note 000 gives no dimensions, mass, surface or residual dipole for the
//! AraMiS cube (§1.2 only puts the body origin at the geometric centre and assumes it is the
//! centre of mass, which would make the aerodynamic and solar-pressure torques vanish: a kinder
//! truth than issue #8's). The only figures the seeds give are seed 004's in-orbit budget for a
//! 3U at 500 km (1.53e-6 N·m: drag over 1.5 × the largest face 0.1 × 0.3405 m with a 72.8 mm
//! arm, 4e-3 A·m² residual dipole, eq. 2.9–2.12), which the testbed thesis adopts as the limit a
//! satellite must cope with. The scenarios keep seed 004's figures, as hard as issue #8's
//! truth: a uniform cube of the flight inertia and seed 004's 4 kg has a 0.134 m side, so
//! 0.027 m² of drag area against the 0.051 m² kept, and the same 4e-3 A·m² residual dipole
//! (1e-3 A·m²/kg, eq. 2.9).
//!
//! # The thesis's satellite
//! `thesis-slew` and `thesis-slew-noisy` (and `acs demo`) reproduce chapter 12 and compare with
//! the thesis's figures, so they fly the thesis's satellite ([`Satellite::Thesis`], a host
//! loop sized to it) and not [`crate::flight::CONFIG`]:
//! - the date is 2009-06-16, before the flight field tables (IGRF 2020–2030): the loop
//!   carries the whole IGRF history at degree 13;
//! - the slew is planned about the thesis's principal axes (its full inertia tensor of §4.2,
//!   `E` of eq. 10.33): the decomposition and the rotation angles the demo prints are the
//!   thesis's only with that tensor;
//! - the thesis's Simulink run has no coils, is sampled at 0.1 s and its wheels reach their
//!   momentum almost at once (0.02 N·m here); the thesis gives no `L_max` (note 000 §3.10):
//!   issue #8 chose 2e-3 kg·m²/s, twice the flight wheels.
//!
//! Its truth is built from its configuration by the same [`spacecraft`].

use crate::acs_loop::{AcsConfig, Command};
use crate::attitude::{Dcm, Euler321, Quaternion};
use crate::control::bdot::BdotConfig;
use crate::control::principal_axes::principal_axes;
use crate::control::slew::SlewLimits;
use crate::control::sun_safe::SunSafeGains;
use crate::control::tracking::TrackingGains;
use crate::env::igrf::{Degree, ModelId, FULL_COEFFS};
use crate::flight::{FlightLoop, CONFIG, TILES};
use crate::linalg::{Mat3, Mat3d, Vec3, Vec3d};
use crate::orbit::sgp4::{Gravity, Sgp4};
use crate::tiles::{Tiles, CUBE_THESIS};
use crate::time::{Calendar, Epoch, Utc};
use crate::two_node::TwoNodeLoop;

use super::realistic::{Realism, TruthLevel};
use super::{run, Disturbances, Sample, SensorNoise, SimConfig, SimError, Simulator};

/// The thesis TLE (DTUSAT, note 000 §3.3 and §4.2).
pub const DTUSAT_TLE: (&str, &str) = (
    "1 27842U 03031C   09166.20608466  .00000024  00000-0  31026-4 0  5778",
    "2 27842  98.7036 176.3713 0009831 124.5029 235.7083 14.20982944309069",
);

/// The thesis's inertia tensor, kg·m² (note 000 §4.2; digits kept as printed).
#[allow(clippy::excessive_precision)]
pub fn thesis_inertia() -> Mat3 {
    Mat3::new(
        0.0072521418,
        -0.000011600796,
        0.000002868117,
        -0.000011600796,
        0.0027406751,
        -0.000056058867,
        0.000002868117,
        -0.000056058867,
        0.0072920283,
    )
}

/// A TLE with correct checksums for a near-circular orbit (B* = 0): `epoch` as `(yy, day)`,
/// angles in degrees, mean motion in rev/day.
pub fn make_tle(
    catalog: u32,
    epoch: (u8, f64),
    incl_deg: f64,
    raan_deg: f64,
    arg_perigee_deg: f64,
    mean_anomaly_deg: f64,
    mean_motion: f64,
) -> (String, String) {
    let checksum = |line: &str| -> u32 {
        line.chars()
            .map(|c| match c {
                '0'..='9' => c.to_digit(10).unwrap_or(0),
                '-' => 1,
                _ => 0,
            })
            .sum::<u32>()
            % 10
    };
    let l1 = format!(
        "1 {catalog:05}U 25001A   {:02}{:012.8}  .00000000  00000-0  00000-0 0  999",
        epoch.0, epoch.1
    );
    let l2 = format!(
        "2 {catalog:05} {incl_deg:8.4} {raan_deg:8.4} 0001000 {arg_perigee_deg:8.4} {mean_anomaly_deg:8.4} {mean_motion:11.8}    1"
    );
    let l1 = format!("{l1}{}", checksum(&l1));
    let l2 = format!("{l2}{}", checksum(&l2));
    (l1, l2)
}

/// Mean motion (rev/day) of a circular orbit at `alt_km`.
pub fn mean_motion_rev_per_day(alt_km: f64) -> f64 {
    let a = 6378.137 + alt_km;
    (398_600.441_8 / (a * a * a)).sqrt() * 86_400.0 / (2.0 * std::f64::consts::PI)
}

/// The satellite a scenario flies: the loop's configuration, and the loop that flies it.
#[derive(Clone, Debug)]
pub enum Satellite {
    /// [`crate::flight::CONFIG`] itself, flown by [`FlightLoop`]: what the firmware flies.
    Flight,
    /// The thesis's satellite (seed 000 ch. 12, [`thesis_config`]), flown by a host loop with
    /// room for the IGRF degree 13 (see the [module docs](self)).
    Thesis(Box<AcsConfig<TILES>>),
}

impl Satellite {
    /// The loop configuration.
    pub fn config(&self) -> &AcsConfig<TILES> {
        match self {
            Self::Flight => &CONFIG,
            Self::Thesis(c) => c,
        }
    }
}

/// The truth's spacecraft built from the loop configuration it flies ([`spacecraft`]).
#[derive(Clone, Debug)]
pub struct Spacecraft {
    /// Inertia in body axes, kg·m² (the configuration's `axes.inertia_body`).
    pub inertia: Mat3d,
    /// The tiles: geometry and equipment.
    pub tiles: Tiles,
    /// The coils: body axis and dipole limit, A·m².
    pub coils: Vec<(Vec3d, f64)>,
    /// The wheels' momentum limit, kg·m²/s.
    pub wheel_max_h_nms: f64,
}

/// The truth's spacecraft built from the loop configuration it flies, so that the two cannot
/// diverge: the inertia in body axes, the tiles (geometry and equipment), the coils (axis and
/// dipole limit) and the wheels' momentum limit. The truth's torque limit, sensors and
/// disturbances are the scenario's.
pub fn spacecraft<const N: usize>(config: &AcsConfig<N>) -> Result<Spacecraft, SimError> {
    let mut tiles = Tiles::new();
    for tile in &config.tiles {
        tiles
            .push(*tile)
            .map_err(|_| SimError::Model("more tiles than the simulator holds".into()))?;
    }
    Ok(Spacecraft {
        inertia: config.axes.inertia_body.cast::<f64>(),
        tiles,
        coils: config
            .coils
            .iter()
            .map(|c| (c.axis_body.cast::<f64>(), f64::from(c.limit)))
            .collect(),
        wheel_max_h_nms: f64::from(config.wheel_limit_nms),
    })
}

/// A runnable scenario.
pub struct Scenario {
    /// Name (`acs sim NAME`).
    pub name: &'static str,
    /// What it shows.
    pub description: &'static str,
    /// Truth configuration.
    pub sim: SimConfig,
    /// The satellite the loop flies (its configuration).
    pub flight: Satellite,
    /// Initial attitude (scalar-first, TEME → body) and body rate (rad/s).
    pub initial: ([f64; 4], Vec3d),
    /// Ground commands (s from start).
    pub commands: Vec<(f64, Command)>,
    /// Target attitude for the pointing error (TEME → body), if any.
    pub target: Option<[f64; 4]>,
    /// Duration and control period, s.
    pub duration_s: f64,
    /// Control period, s.
    pub dt_s: f64,
    /// Gravity model of the flight SGP4.
    pub gravity: Gravity,
}

impl Scenario {
    /// The flight SGP4 of the scenario's TLE (flight operations initialise it on the ground).
    pub fn orbit(&self) -> Result<Sgp4, SimError> {
        let tle = crate::tle::Tle::parse(&self.sim.tle.0, &self.sim.tle.1)
            .map_err(|e| SimError::Tle(e.to_string()))?;
        Sgp4::new(&tle, self.gravity).map_err(|e| SimError::Model(format!("{e:?}")))
    }

    /// The scenario flown against `truth` (every constructor gives the realistic truth).
    pub fn with_truth(mut self, truth: TruthLevel) -> Self {
        self.sim.realism = match truth {
            TruthLevel::Ideal => None,
            TruthLevel::Realistic => Some(Realism::DEFAULT),
        };
        self
    }

    /// The truth the scenario flies.
    pub fn truth(&self) -> TruthLevel {
        if self.sim.realism.is_some() {
            TruthLevel::Realistic
        } else {
            TruthLevel::Ideal
        }
    }

    /// The simulator in the scenario's initial state.
    pub fn simulator(&self) -> Result<Simulator, SimError> {
        Simulator::new(self.sim.clone(), self.initial.0, self.initial.1)
    }

    /// Runs the scenario: the samples of every control period. [`Satellite::Flight`] is flown
    /// by [`FlightLoop`] over [`crate::flight::CONFIG`], the thesis's satellite by the same two
    /// nodes composed with room for its degree-13 field.
    pub fn run(&self) -> Result<Vec<Sample>, SimError> {
        let orbit = self.orbit()?;
        let refused = |e: crate::acs_loop::AcsError| SimError::Model(e.to_string());
        match &self.flight {
            Satellite::Flight => {
                let mut acs = FlightLoop::new(&CONFIG, orbit).map_err(refused)?;
                self.fly(&mut acs)
            }
            Satellite::Thesis(config) => {
                let mut acs =
                    TwoNodeLoop::<TILES, FULL_COEFFS>::new(config, orbit).map_err(refused)?;
                self.fly(&mut acs)
            }
        }
    }

    /// Flies `acs` (a loop over [`Scenario::flight`]'s configuration) against a fresh
    /// simulator with the scenario's commands.
    pub fn fly<const N: usize, const F: usize>(
        &self,
        acs: &mut TwoNodeLoop<'_, N, F>,
    ) -> Result<Vec<Sample>, SimError> {
        let mut sim = self.simulator()?;
        let target = self.target;
        run(
            &mut sim,
            acs,
            self.duration_s,
            self.dt_s,
            &self.commands,
            move |_| target,
        )
    }
}
fn quat_f64(q: &Quaternion) -> [f64; 4] {
    [
        f64::from(q.q0),
        f64::from(q.q1),
        f64::from(q.q2),
        f64::from(q.q3),
    ]
}

/// `y-mo-d h:00:00` UTC.
pub(super) fn epoch(y: i32, mo: u8, d: u8, h: u8) -> Result<Epoch<Utc>, SimError> {
    Epoch::from_calendar(Calendar {
        year: y,
        month: mo,
        day: d,
        hour: h,
        minute: 0,
        second: 0,
        nano: 0,
    })
    .map_err(|e| SimError::Model(e.to_string()))
}

fn thesis_noise(percent: bool) -> SensorNoise {
    if percent {
        // about 1 % of each reading, as the thesis's Test 2 (note 000 §4.4)
        SensorNoise {
            sun_rad: 0.01,
            mag_nt: 300.0,
            mag_bias_nt: 0.0,
            gyro_radps: 1e-4,
            gyro_bias_radps: 0.0,
            dropout: 0.0,
        }
    } else {
        SensorNoise::IDEAL
    }
}

/// Torque of the thesis's wheels, N·m: they reach their momentum almost at once (see the
/// [module docs](self)); the truth's wheels and the loop's limit.
const THESIS_WHEEL_TORQUE_NM: f64 = 0.02;

/// The thesis's satellite (seed 000 ch. 12; see the [module docs](self)): its inertia tensor
/// (§4.2) and the principal axes of it, the cube's tiles (§1.2), no coils, 2e-3 kg·m²/s wheels
/// of 0.02 N·m, a 0.1 s period, IGRF degree 13 over the whole history (the date is 2009).
pub fn thesis_config() -> Result<AcsConfig<TILES>, SimError> {
    let inertia = thesis_inertia();
    let axes = principal_axes(&inertia).map_err(|e| SimError::Model(e.to_string()))?;
    let wheel_limit = 2e-3;
    let i_max = inertia.diagonal().max();
    Ok(AcsConfig {
        tiles: heapless::Vec::from_array(CUBE_THESIS),
        axes,
        coils: heapless::Vec::new(),
        wheel_limit_nms: wheel_limit,
        wheel_torque_nm: Vec3::from_element(THESIS_WHEEL_TORQUE_NM as f32),
        bdot: BdotConfig {
            gain: 3.0e4,
            max_dipole_am2: Vec3::from_element(0.2),
        },
        tracking: TrackingGains::from_bandwidth(&inertia, 0.25, 0.9),
        // 1 rad/s at the 0.1 s period (ω T = 0.1): over 10 000 dispersed runs (10 % inertia)
        // the closed-loop slew's end 0.17° at the median, 0.29° at p99 (with 1: 1.45°, 3.61°)
        slew_gain_factor: 4.0,
        sun_safe: SunSafeGains {
            kp_nm: 2.0 * 0.05 * 0.05 * i_max,
            kd_nms: 2.0 * 0.05 * i_max,
        },
        sun_axis_body: Vec3::z(),
        slew_limits: SlewLimits {
            l_max: wheel_limit,
            l_min: 1e-7,
            t_min: 0.3,
            default_fraction: 0.85,
            wheels_per_axis: [1, 2, 2],
        },
        slew_pause_s: 5.0,
        control_period_s: 0.1,
        dumping_gain_per_s: 0.0,
        detumble_enter_radps: 3.0,
        detumble_exit_radps: 0.01,
        igrf_model: ModelId::Full,
        igrf_degree: Degree::FULL,
        // the thesis's test has no albedo (seed 000 ch. 12)
        filter: crate::determination::mekf::MekfConfig {
            earth_albedo: 0.0,
            ..crate::flight::FILTER
        },
    })
}

/// The thesis scenario (seed 000 ch. 12): DTUSAT on 2009-06-16 00:00 UTC, true attitude A
/// (3-2-1: Φ = 0, θ = −30°, Ψ = −45°), slew to `A_d` = 90° about I by the thesis's plan
/// (shortest branch) flown in closed loop ([`crate::control::slew_trajectory`]; the thesis flew
/// it open loop), then tracking. `noisy`: about 1 % sensor noise. The thesis's own
/// satellite ([`thesis_config`]), no disturbances.
pub fn thesis_slew(noisy: bool) -> Result<Scenario, SimError> {
    let flight = thesis_config()?;
    let Spacecraft {
        inertia,
        tiles,
        coils,
        wheel_max_h_nms,
    } = spacecraft(&flight)?;
    let a_true = Dcm::from_euler_321(&Euler321 {
        phi_rad: 0.0,
        theta_rad: (-30f32).to_radians(),
        psi_rad: (-45f32).to_radians(),
    });
    let a_d = Dcm::from_matrix_unchecked(Mat3::new(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0));
    let q_true = a_true.to_quaternion();
    let q_d = a_d.to_quaternion();
    let sim = SimConfig {
        tle: (DTUSAT_TLE.0.to_string(), DTUSAT_TLE.1.to_string()),
        start: epoch(2009, 6, 16, 0)?,
        inertia,
        tiles,
        coils,
        wheel_max_h_nms,
        wheel_axes_body: vec![],
        wheel_max_torque_nm: THESIS_WHEEL_TORQUE_NM,
        sun_fov_rad: 80f64.to_radians(),
        noise: thesis_noise(noisy),
        disturbances: Disturbances::none(),
        failures: vec![],
        substep_s: 0.05,
        seed: 7,
        realism: Some(Realism::DEFAULT),
    };
    Ok(Scenario {
        name: if noisy {
            "thesis-slew-noisy"
        } else {
            "thesis-slew"
        },
        description:
            "seed 000 ch. 12, the thesis's satellite: hold A, slew to A_d (90° about I) by the plan flown in closed loop, then track",
        sim,
        flight: Satellite::Thesis(Box::new(flight)),
        initial: (quat_f64(&q_true), Vec3d::zeros()),
        commands: vec![
            (0.0, Command::Track { target: q_true }),
            (
                60.0,
                Command::Slew {
                    target: a_d,
                    within_s: 120.0,
                },
            ),
        ],
        target: Some(quat_f64(&q_d)),
        duration_s: 240.0,
        // the loop's 0.1 s (f32) period; the truth's clock steps the f64 0.1 s
        dt_s: 0.1,
        gravity: Gravity::Wgs84,
    })
}

/// The truth of a scenario flying [`crate::flight::CONFIG`] on `tle` from 2025-03-20 12:00 UTC:
/// the spacecraft built from the constant ([`spacecraft`]), 1e-3 N·m wheel torque, 80° Sun
/// sensors, seed 004's disturbances (see the [module docs](self)).
fn flight_truth(
    tle: (String, String),
    noise: SensorNoise,
    failures: Vec<(usize, f64)>,
    seed: u64,
) -> Result<SimConfig, SimError> {
    let Spacecraft {
        inertia,
        tiles,
        coils,
        wheel_max_h_nms,
    } = spacecraft(&CONFIG)?;
    Ok(SimConfig {
        tle,
        start: epoch(2025, 3, 20, 12)?,
        inertia,
        tiles,
        coils,
        wheel_max_h_nms,
        wheel_axes_body: vec![],
        wheel_max_torque_nm: 1e-3,
        sun_fov_rad: 80f64.to_radians(),
        noise,
        disturbances: Disturbances::seed004(),
        failures,
        substep_s: 0.1,
        seed,
        realism: Some(Realism::DEFAULT),
    })
}

/// The flight control period, s.
fn flight_period_s() -> f64 {
    f64::from(CONFIG.control_period_s)
}

/// The sensors of the detumble and sun-safe scenarios: 1 mrad Sun, 100 nT field with a 50 nT
/// bias, 1e-4 rad/s rate with a 2e-5 rad/s bias, no dropouts.
const NOISE_BIASED: SensorNoise = SensorNoise {
    sun_rad: 1e-3,
    mag_nt: 100.0,
    mag_bias_nt: 50.0,
    gyro_radps: 1e-4,
    gyro_bias_radps: 2e-5,
    dropout: 0.0,
};

/// Detumbling the flight satellite ([`crate::flight::CONFIG`]: diag(0.010, 0.012, 0.014)
/// kg·m², three 0.2 A·m² coils) on a 500 km, 97° orbit, from 10°/s on each axis.
pub fn detumble() -> Result<Scenario, SimError> {
    let tle = make_tle(
        90100,
        (25, 79.5),
        97.0,
        30.0,
        0.0,
        0.0,
        mean_motion_rev_per_day(500.0),
    );
    let w = 10f64.to_radians();
    Ok(Scenario {
        name: "detumble",
        description: "flight configuration, 500 km 97°, B-dot from 10°/s per axis",
        sim: flight_truth(tle, NOISE_BIASED, vec![], 11)?,
        flight: Satellite::Flight,
        initial: ([1.0, 0.0, 0.0, 0.0], Vec3d::new(w, w, w)),
        commands: vec![],
        target: None,
        duration_s: 3.0 * 94.6 * 60.0,
        dt_s: flight_period_s(),
        gravity: Gravity::Wgs72,
    })
}

/// Tracking with wheels and noisy tiles on a dawn-dusk orbit (no eclipse), flying
/// [`crate::flight::CONFIG`]: hold an inertial attitude from an initial 20° error.
/// `failed_tile`: that tile fails at 600 s. The requirement "< 0.1° within one orbit and after"
/// (`docs/closed-loop.md`) is met in the ideal truth since the flight field model is degree 13
/// (issue #29); with the degree-8 model before, whose truncation alone turns the attitude about
/// the Sun line by up to 0.11° on this orbit, it was not (`tests/closed_loop.rs` prints both).
pub fn tracking(failed_tile: Option<usize>) -> Result<Scenario, SimError> {
    // dawn-dusk: the orbit normal near the Sun at the March equinox (RAAN 90°)
    let tle = make_tle(
        90101,
        (25, 79.5),
        97.4,
        90.0,
        0.0,
        0.0,
        mean_motion_rev_per_day(500.0),
    );
    let target = Dcm::a3(0.6).then(&Dcm::a1(-0.3)).to_quaternion();
    let start = Dcm::a2(0.35)
        .then(&Dcm::a3(0.6))
        .then(&Dcm::a1(-0.3))
        .to_quaternion();
    let sim = flight_truth(
        tle,
        SensorNoise {
            sun_rad: 1e-3,
            mag_nt: 100.0,
            mag_bias_nt: 0.0,
            gyro_radps: 1e-4,
            gyro_bias_radps: 0.0,
            dropout: 0.001,
        },
        failed_tile.map(|t| vec![(t, 600.0)]).unwrap_or_default(),
        5,
    )?;
    Ok(Scenario {
        name: if failed_tile.is_some() {
            "failed-tile"
        } else {
            "tracking"
        },
        description: if failed_tile.is_some() {
            "flight configuration tracking with wheels; tile 2 (+W: sun, magnetometer, gyro, wheel) fails at 600 s"
        } else {
            "flight configuration tracking an inertial attitude with wheels and noisy tiles, dawn-dusk orbit"
        },
        sim,
        flight: Satellite::Flight,
        initial: (quat_f64(&start), Vec3d::zeros()),
        commands: vec![(1.0, Command::Track { target })],
        target: Some(quat_f64(&target)),
        duration_s: 94.6 * 60.0,
        dt_s: flight_period_s(),
        gravity: Gravity::Wgs72,
    })
}

/// The right ascension of the ascending node of `tracking-eclipse`, degrees: β = 0 at its start.
///
/// The Sun at 2025-03-20 12:00 UTC (TEME, [`crate::env::sun::precise`]; `acs sun --frame teme`)
/// is at right ascension α = 0.1128°, declination δ = 0.0490° (the equinox was at 09:01 UTC). An
/// orbit of inclination `i` and node Ω has the normal (sin i sin Ω, −sin i cos Ω, cos i), so
/// sin β = sin i cos δ sin(Ω − α) + cos i sin δ, which vanishes at Ω = α − asin(tan δ / tan i) =
/// 0.1128° + 0.0064° for i = 97.4°. The orbit is sun-synchronous: the node follows the Sun and β
/// stays within 0.01° over the three orbits (`tests/closed_loop.rs`, `tracking_eclipse`, measures
/// it from the truth's orbit and Sun).
pub const ECLIPSE_RAAN_DEG: f64 = 0.1192;

/// `tracking` on a noon-midnight orbit: the same satellite, sensors, initial error, command and
/// inertial target as [`tracking`]`(None)` (the Sun is where it is there in the body: the target
/// is inertial and the date the same), on a 500 km, 97.4° sun-synchronous orbit whose plane holds
/// the Sun (β ≈ 0, [`ECLIPSE_RAAN_DEG`]): the longest umbra a 500 km orbit has, about 35.7 min of
/// its 94.6 (cylindrical shadow: the fraction acos(√(h² + 2R⊕h)/r)/π = 0.378 of the orbit). It
/// starts at the ascending node, under the Sun (noon), and flies three orbits and a minute: the
/// first orbit (the acquisition, one umbra), then two full orbits, each with a whole umbra (issue
/// #30: the attitude through eclipse).
pub fn tracking_eclipse() -> Result<Scenario, SimError> {
    let base = tracking(None)?;
    let tle = make_tle(
        90103,
        (25, 79.5),
        97.4,
        ECLIPSE_RAAN_DEG,
        0.0,
        0.0,
        mean_motion_rev_per_day(500.0),
    );
    Ok(Scenario {
        name: "tracking-eclipse",
        description: "flight configuration tracking an inertial attitude with wheels and noisy tiles, noon-midnight orbit (β ≈ 0, the longest umbra), three orbits",
        sim: SimConfig { tle, ..base.sim },
        duration_s: 3.0 * 94.6 * 60.0 + 60.0,
        ..base
    })
}

/// A slew with the flight configuration on the `tracking` orbit and sensors: hold the
/// `tracking` target from rest, at 120 s slew 90° about the body x axis by the thesis's plan
/// flown in closed loop ([`crate::control::slew_trajectory`]) within 300 s, then track the new
/// attitude; 1 200 control periods.
pub fn slew() -> Result<Scenario, SimError> {
    let base = tracking(None)?;
    let hold = Dcm::a3(0.6).then(&Dcm::a1(-0.3));
    let target = hold.then(&Dcm::a1(core::f32::consts::FRAC_PI_2));
    Ok(Scenario {
        name: "slew",
        description: "flight configuration: hold, slew 90° by the plan flown in closed loop within 300 s, then track; dawn-dusk orbit, noisy tiles",
        initial: (quat_f64(&hold.to_quaternion()), Vec3d::zeros()),
        commands: vec![
            (
                1.0,
                Command::Track {
                    target: hold.to_quaternion(),
                },
            ),
            (
                120.0,
                Command::Slew {
                    target,
                    within_s: 300.0,
                },
            ),
        ],
        target: Some(quat_f64(&target.to_quaternion())),
        duration_s: 1200.0,
        ..base
    })
}

/// Sun-safe acquisition through a whole eclipse, flying [`crate::flight::CONFIG`]:
/// noon-midnight orbit (full-length eclipses), starting tumbling slowly.
pub fn sun_safe() -> Result<Scenario, SimError> {
    let tle = make_tle(
        90102,
        (25, 79.5),
        97.4,
        0.0,
        0.0,
        0.0,
        mean_motion_rev_per_day(500.0),
    );
    let w = 0.3f64.to_radians();
    Ok(Scenario {
        name: "sun-safe",
        description:
            "flight configuration, sun-safe from a slow tumble, one orbit with a full eclipse",
        sim: flight_truth(tle, NOISE_BIASED, vec![], 3)?,
        flight: Satellite::Flight,
        initial: ([1.0, 0.0, 0.0, 0.0], Vec3d::new(w, -w, w)),
        commands: vec![],
        target: None,
        duration_s: 94.6 * 60.0,
        dt_s: flight_period_s(),
        gravity: Gravity::Wgs72,
    })
}

/// A built-in scenario by name, flown against `truth`.
pub fn by_name_with(name: &str, truth: TruthLevel) -> Option<Result<Scenario, SimError>> {
    by_name(name).map(|s| s.map(|s| s.with_truth(truth)))
}

/// All built-in scenarios by name (the realistic truth).
pub fn by_name(name: &str) -> Option<Result<Scenario, SimError>> {
    Some(match name {
        "thesis-slew" => thesis_slew(false),
        "thesis-slew-noisy" => thesis_slew(true),
        "detumble" => detumble(),
        "tracking" => tracking(None),
        "tracking-eclipse" => tracking_eclipse(),
        "failed-tile" => tracking(Some(2)),
        "slew" => slew(),
        "sun-safe" => sun_safe(),
        _ => return None,
    })
}

/// Names of the built-in scenarios.
pub const NAMES: [&str; 8] = [
    "detumble",
    "thesis-slew",
    "thesis-slew-noisy",
    "sun-safe",
    "tracking",
    "failed-tile",
    "slew",
    "tracking-eclipse",
];
