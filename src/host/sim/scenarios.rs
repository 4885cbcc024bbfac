//! Built-in closed-loop scenarios: the thesis slew (seed 000 ch. 12), detumbling a 3U-class
//! spacecraft, sun-safe acquisition, tracking with wheels, a failed tile, and a whole eclipse.
//!
//! Each scenario is plain data: the truth configuration, the flight configuration, the initial
//! state, the ground commands and the target attitude the pointing error is measured against.

use crate::acs_loop::{AcsConfig, AcsLoop, Command};
use crate::attitude::{Dcm, Euler321, Quaternion};
use crate::control::bdot::BdotConfig;
use crate::control::principal_axes::principal_axes;
use crate::control::slew::SlewLimits;
use crate::control::sun_safe::SunSafeGains;
use crate::control::tracking::TrackingGains;
use crate::control::wheels::Wheel;
use crate::env::igrf::{Degree, FULL};
use crate::linalg::{Mat3, Vec3, Vec3d};
use crate::orbit::sgp4::{Gravity, Sgp4};
use crate::tiles::cube_thesis;
use crate::time::{Calendar, Epoch, Utc};

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

/// Flight configuration shared by the scenarios: the thesis's cube tiles.
fn flight_config(
    inertia: Mat3,
    coils: &[(Vec3, f32)],
    wheel_limit: f32,
) -> Result<AcsConfig, SimError> {
    let axes = principal_axes(&inertia).map_err(|e| SimError::Model(e.to_string()))?;
    let mut coil_vec = heapless::Vec::new();
    for (axis, limit) in coils {
        coil_vec
            .push(Wheel {
                axis_body: *axis,
                limit: *limit,
                working: true,
            })
            .map_err(|_| SimError::Model("too many coils".into()))?;
    }
    Ok(AcsConfig {
        tiles: cube_thesis(),
        axes,
        coils: coil_vec,
        wheel_limit_nms: wheel_limit,
        bdot: BdotConfig {
            gain: 3.0e4,
            max_dipole_am2: Vec3::from_element(coils.first().map_or(0.2, |c| c.1)),
        },
        tracking: TrackingGains::from_bandwidth(&inertia, 0.25, 0.9),
        sun_safe: SunSafeGains {
            kp_nm: 2.0 * 0.05 * 0.05 * inertia.diagonal().max(),
            kd_nms: 2.0 * 0.05 * inertia.diagonal().max(),
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
        control_period_s: 1.0,
        dumping_gain_per_s: if coils.is_empty() { 0.0 } else { 1e-3 },
        detumble_enter_radps: 0.5,
        detumble_exit_radps: 0.5f32.to_radians(),
        igrf_model: &FULL,
        igrf_degree: Degree::FULL,
        weights: (1.0, 1.0),
        filter_gain: 0.1,
        max_propagation_s: 120.0,
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
    /// Flight configuration.
    pub flight: AcsConfig,
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
    /// Runs the scenario: the samples of every control period.
    pub fn run(&self) -> Result<Vec<Sample>, SimError> {
        let tle = crate::tle::Tle::parse(&self.sim.tle.0, &self.sim.tle.1)
            .map_err(|e| SimError::Tle(e.to_string()))?;
        let orbit = Sgp4::new(&tle, self.gravity).map_err(|e| SimError::Model(format!("{e:?}")))?;
        let mut acs: AcsLoop =
            AcsLoop::new(&self.flight, orbit).map_err(|e| SimError::Model(e.to_string()))?;
        let mut sim = Simulator::new(self.sim.clone(), self.initial.0, self.initial.1)?;
        let target = self.target;
        run(
            &mut sim,
            &mut acs,
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

fn epoch(y: i32, mo: u8, d: u8, h: u8) -> Result<Epoch<Utc>, SimError> {
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

/// The thesis scenario (seed 000 ch. 12): DTUSAT on 2009-06-16 00:00 UTC, true attitude A
/// (3-2-1: Φ = 0, θ = −30°, Ψ = −45°), slew to `A_d` = 90° about I by the thesis's open-loop
/// plan (shortest branch), then tracking. `noisy`: about 1 % sensor noise.
pub fn thesis_slew(noisy: bool) -> Result<Scenario, SimError> {
    let inertia = thesis_inertia();
    let flight = {
        let mut f = flight_config(inertia, &[], 2e-3)?;
        f.detumble_enter_radps = 3.0;
        f.detumble_exit_radps = 0.01;
        f.control_period_s = 0.1;
        f
    };
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
        inertia: inertia.cast::<f64>(),
        tiles: cube_thesis(),
        coils: vec![],
        wheel_max_h_nms: 2e-3,
        wheel_max_torque_nm: 0.02,
        sun_fov_rad: 80f64.to_radians(),
        noise: thesis_noise(noisy),
        disturbances: Disturbances::none(),
        failures: vec![],
        substep_s: 0.05,
        seed: 7,
    };
    Ok(Scenario {
        name: if noisy {
            "thesis-slew-noisy"
        } else {
            "thesis-slew"
        },
        description:
            "seed 000 ch. 12: hold A, slew to A_d (90° about I) by the open-loop plan, then track",
        sim,
        flight,
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
        dt_s: 0.1,
        gravity: Gravity::Wgs84,
    })
}

/// The 3U-class spacecraft of issue #8 (inertia diag(0.042, 0.042, 0.0067) kg·m², three
/// 0.2 A·m² coils, 0.01 kg·m²/s wheels, the thesis's cube tiles for sensor geometry, seed 004
/// disturbances) on `tle`, starting 2025-03-20 12:00 UTC: the truth and flight configurations.
fn cubesat_3u(
    tle: (String, String),
    noise: SensorNoise,
    failures: Vec<(usize, f64)>,
    seed: u64,
) -> Result<(SimConfig, AcsConfig), SimError> {
    let inertia = Mat3::from_diagonal(&Vec3::new(0.042, 0.042, 0.0067));
    let coils = [(Vec3::x(), 0.2), (Vec3::y(), 0.2), (Vec3::z(), 0.2)];
    let flight = flight_config(inertia, &coils, 0.01)?;
    let sim = SimConfig {
        tle,
        start: epoch(2025, 3, 20, 12)?,
        inertia: inertia.cast::<f64>(),
        tiles: cube_thesis(),
        coils: coils
            .iter()
            .map(|(a, l)| (a.cast::<f64>(), f64::from(*l)))
            .collect(),
        wheel_max_h_nms: 0.01,
        wheel_max_torque_nm: 1e-3,
        sun_fov_rad: 80f64.to_radians(),
        noise,
        disturbances: Disturbances::seed004(),
        failures,
        substep_s: 0.1,
        seed,
    };
    Ok((sim, flight))
}

/// The 3U CubeSat's sensors in the detumble and sun-safe scenarios: 1 mrad Sun, 100 nT field
/// with a 50 nT bias, 1e-4 rad/s rate with a 2e-5 rad/s bias, no dropouts.
const CUBESAT_NOISE: SensorNoise = SensorNoise {
    sun_rad: 1e-3,
    mag_nt: 100.0,
    mag_bias_nt: 50.0,
    gyro_radps: 1e-4,
    gyro_bias_radps: 2e-5,
    dropout: 0.0,
};

/// The 3U-class detumble of issue #8: inertia diag(0.042, 0.042, 0.0067) kg·m², 0.2 A·m² per
/// axis, 500 km, 97°, from 10°/s on each axis.
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
    let (sim, flight) = cubesat_3u(tle, CUBESAT_NOISE, vec![], 11)?;
    Ok(Scenario {
        name: "detumble",
        description: "3U, 500 km 97°, B-dot from 10°/s per axis",
        sim,
        flight,
        initial: ([1.0, 0.0, 0.0, 0.0], Vec3d::new(w, w, w)),
        commands: vec![],
        target: None,
        duration_s: 3.0 * 94.6 * 60.0,
        dt_s: 1.0,
        gravity: Gravity::Wgs72,
    })
}

/// Tracking with wheels and noisy tiles on a dawn-dusk orbit (no eclipse): hold an inertial
/// attitude from an initial 20° error.
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
    let (sim, flight) = cubesat_3u(
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
            "tracking with wheels; tile 2 (+W: sun, magnetometer, gyro, wheel) fails at 600 s"
        } else {
            "tracking an inertial attitude with wheels and noisy tiles, dawn-dusk orbit"
        },
        sim,
        flight,
        initial: (quat_f64(&start), Vec3d::zeros()),
        commands: vec![(1.0, Command::Track { target })],
        target: Some(quat_f64(&target)),
        duration_s: 94.6 * 60.0,
        dt_s: 1.0,
        gravity: Gravity::Wgs72,
    })
}

/// Sun-safe acquisition through a whole eclipse: noon-midnight orbit (full-length eclipses),
/// starting tumbling slowly.
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
    let (sim, flight) = cubesat_3u(tle, CUBESAT_NOISE, vec![], 3)?;
    Ok(Scenario {
        name: "sun-safe",
        description: "sun-safe from a slow tumble, one orbit with a full eclipse",
        sim,
        flight,
        initial: ([1.0, 0.0, 0.0, 0.0], Vec3d::new(w, -w, w)),
        commands: vec![],
        target: None,
        duration_s: 94.6 * 60.0,
        dt_s: 1.0,
        gravity: Gravity::Wgs72,
    })
}

/// All built-in scenarios by name.
pub fn by_name(name: &str) -> Option<Result<Scenario, SimError>> {
    Some(match name {
        "thesis-slew" => thesis_slew(false),
        "thesis-slew-noisy" => thesis_slew(true),
        "detumble" => detumble(),
        "tracking" => tracking(None),
        "failed-tile" => tracking(Some(2)),
        "sun-safe" => sun_safe(),
        _ => return None,
    })
}

/// Names of the built-in scenarios.
pub const NAMES: [&str; 6] = [
    "detumble",
    "thesis-slew",
    "thesis-slew-noisy",
    "sun-safe",
    "tracking",
    "failed-tile",
];
