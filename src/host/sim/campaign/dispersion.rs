//! What a campaign disperses, per scenario, each with its distribution and the source of its
//! default: [`Dispersions::of`] is the one place they are declared.
//!
//! | what | distribution (default) | source |
//! |---|---|---|
//! | initial attitude | the scenario's, turned about a uniformly random axis by a Gaussian angle (1σ 5° for the pointing scenarios, 1° for the thesis slews); or uniformly random (detumble, sun-safe) | assumption: what the loop is handed by the mode before; a tumbling satellite has any attitude |
//! | initial rate | a Gaussian rate added per axis (1σ 0.05°/s pointing, 0.01°/s thesis); or the scenario's magnitude in a uniformly random direction, scaled uniformly by ±10 % (detumble) or ±50 % (sun-safe) | assumption: residual rates after detumbling; tip-off rates of the detumble requirement |
//! | inertia | each principal moment scaled uniformly by ±10 %, principal axes turned by 1σ 2° about each body axis | issue #21 (±10 %, a few degrees): a CAD estimate before the satellite is weighed |
//! | centre of mass | 1σ 5 mm per body axis from the geometric centre (moves the centre of pressure) | assumption: seed 004 §2.1 budgets a 72.8 mm drag arm; the integrated cube's CoM is known to a few mm |
//! | residual dipole | Gaussian per body axis, 1σ 4e-3/√3 A·m² (RMS magnitude 4e-3 A·m²) | seed 004 §2.1 (4e-3 A·m², 1e-3 A·m²/kg) |
//! | orbit epoch | uniform over one year after the scenario's date; a sun-synchronous orbit's ascending node follows the mean Sun (0.9856°/day) so its local time stays, and the scenario's inertial attitudes (initial, target, commands) turn with it about the TEME z axis, so that the pointing keeps its place relative to the orbit and the mean Sun (what a mission does: it chooses its target for its date); the season then moves the Sun's declination against the orbit, and the time of day the Earth's field; mean anomaly uniform over 360° (the thesis slews: uniform over the day after their date, their TLE and attitudes unchanged) | issue #21: the epoch also moves the eclipse season and the Sun–field geometry |
//! | atmospheric density | log-uniform between solar minimum and maximum (factor 0.1–1 of the truth's maximum) | seed 002 §3.3 (10× smaller at solar minimum), seed 004 §2.1 (maximum) |
//! | wheel momentum scale | 1σ 1 % per wheel | assumption: rotor inertia known to 1 % |
//! | wheel axis | 1σ 0.5° tilt about each tile axis per wheel | assumption: wheel on tile, tile on structure |
//! | coil axis | 1σ 0.5° tilt per coil | assumption, as the wheels |
//! | sensors (noise, bias, scale factor, misalignment per tile; magnetometer offsets), coil scale factors, the spacecraft's own fields, the unmodelled field | drawn per device by the realistic truth's tables from the run's seed ([`crate::host::sim::realistic`]); in the ideal truth the scenario's [`crate::host::sim::SensorNoise`] biases | `docs/simulator.md` |
//!
//! Every draw is a pure function of the run's seed ([`super::run_seed`]), so a run is
//! reproducible alone.

use crate::acs_loop::Command;
use crate::attitude::Quaternion;
use crate::linalg::{Mat3d, Vec3d};
use crate::orbit::sgp4::Sgp4;
use crate::time::{Epoch, TimeSpan, Utc};

use super::super::scenarios::{self, make_tle, Scenario};
use super::super::{dcm_of, Rng, SimError};

/// How the initial attitude is dispersed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AttitudeDispersion {
    /// The scenario's attitude turned about a uniformly random axis by a Gaussian angle of this
    /// 1σ, rad.
    Gaussian(f64),
    /// Any attitude (uniform over the rotations).
    Uniform,
}

/// How the initial body rate is dispersed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RateDispersion {
    /// The scenario's rate plus a Gaussian of this 1σ per body axis, rad/s.
    Added(f64),
    /// The scenario's rate magnitude in a uniformly random direction, scaled uniformly within
    /// ± this fraction.
    RandomDirection(f64),
}

/// How the orbit epoch is dispersed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EpochDispersion {
    /// The scenario's TLE moved uniformly over this many days after its epoch, the ascending
    /// node following the mean Sun (sun-synchronous), the mean anomaly uniform over 360°.
    SunSynchronous(f64),
    /// The start moved uniformly over this many days after the scenario's, the TLE kept.
    Start(f64),
}

/// The dispersions of one scenario (the [module docs](self) give each default's source).
#[derive(Clone, Debug, PartialEq)]
pub struct Dispersions {
    /// Initial attitude.
    pub attitude: AttitudeDispersion,
    /// Initial body rate.
    pub rate: RateDispersion,
    /// Half range of the uniform scale of each principal moment of inertia (fraction).
    pub inertia_moments: f64,
    /// 1σ turn of the principal axes about each body axis, rad.
    pub inertia_axes_rad: f64,
    /// 1σ offset of the centre of mass per body axis, m.
    pub com_offset_m: f64,
    /// 1σ residual dipole per body axis, A·m².
    pub residual_dipole_am2: f64,
    /// Orbit epoch.
    pub epoch: EpochDispersion,
    /// Range of the log-uniform atmospheric density factor.
    pub density_factor: (f64, f64),
    /// 1σ wheel momentum scale error (fraction).
    pub wheel_scale: f64,
    /// 1σ wheel axis tilt about each axis, rad.
    pub wheel_axis_rad: f64,
    /// 1σ coil axis tilt about each axis, rad.
    pub coil_axis_rad: f64,
}

/// The names of the dispersed values a run records ([`Drawn`]), in order.
pub const DRAWN: [&str; 11] = [
    "attitude_offset_deg",
    "rate_degps",
    "inertia_x_scale",
    "inertia_y_scale",
    "inertia_z_scale",
    "inertia_axes_deg",
    "com_offset_mm",
    "residual_dipole_am2",
    "epoch_offset_days",
    "density_factor",
    "wheel_scale_max_error",
];

/// The dispersed values of one run, in the order of [`DRAWN`].
pub type Drawn = [f64; 11];

const DEG: f64 = std::f64::consts::PI / 180.0;

impl Dispersions {
    /// The dispersions of the built-in scenario `name` (the [module docs](self)).
    pub fn of(name: &str) -> Self {
        let common = Self {
            attitude: AttitudeDispersion::Gaussian(5.0 * DEG),
            rate: RateDispersion::Added(0.05 * DEG),
            inertia_moments: 0.10,
            inertia_axes_rad: 2.0 * DEG,
            com_offset_m: 0.005,
            residual_dipole_am2: 4e-3 / 3f64.sqrt(),
            epoch: EpochDispersion::SunSynchronous(365.25),
            density_factor: (0.1, 1.0),
            wheel_scale: 0.01,
            wheel_axis_rad: 0.5 * DEG,
            coil_axis_rad: 0.5 * DEG,
        };
        match name {
            "detumble" => Self {
                attitude: AttitudeDispersion::Uniform,
                rate: RateDispersion::RandomDirection(0.10),
                ..common
            },
            "sun-safe" => Self {
                attitude: AttitudeDispersion::Uniform,
                rate: RateDispersion::RandomDirection(0.50),
                ..common
            },
            "thesis-slew" | "thesis-slew-noisy" => Self {
                attitude: AttitudeDispersion::Gaussian(1.0 * DEG),
                rate: RateDispersion::Added(0.01 * DEG),
                epoch: EpochDispersion::Start(1.0),
                ..common
            },
            _ => common,
        }
    }

    /// Disperses `scenario` for the run seeded `seed`: the truth's spacecraft, orbit and
    /// environment and the initial state change; the loop's configuration does not (it flies
    /// what it believes). The truth's own random draws (sensors, fields) take `seed`.
    pub fn apply(&self, scenario: &mut Scenario, seed: u64) -> Result<Drawn, SimError> {
        let mut rng = Rng::new(seed ^ 0xD15C_E25E_0000_0021);
        scenario.sim.seed = seed;

        // epoch
        let sim = &mut scenario.sim;
        let days = match self.epoch {
            EpochDispersion::SunSynchronous(span) => {
                let days = span * rng.uniform();
                let anomaly = 360.0 * rng.uniform();
                let tle = crate::tle::Tle::parse(&sim.tle.0, &sim.tle.1)
                    .map_err(|e| SimError::Tle(e.to_string()))?;
                let start = tle.epoch.add(seconds(days * 86_400.0)?);
                let raan = (tle.raan_deg + days * 360.0 / 365.242_2).rem_euclid(360.0);
                let (l1, l2) = make_tle(
                    tle.catalog_number,
                    tle_epoch(&start)?,
                    tle.inclination_deg,
                    raan,
                    tle.arg_perigee_deg,
                    anomaly,
                    tle.mean_motion_rev_per_day,
                );
                let parsed =
                    crate::tle::Tle::parse(&l1, &l2).map_err(|e| SimError::Tle(e.to_string()))?;
                // the run starts at its element set's epoch, as the scenario does
                sim.start = parsed.epoch;
                Sgp4::new(&parsed, scenario.gravity)
                    .map_err(|e| SimError::Model(format!("{e:?}")))?;
                sim.tle = (l1, l2);
                // the pointing keeps its place relative to the orbit and the mean Sun
                turn_reference(scenario, (days * 360.0 / 365.242_2).to_radians());
                days
            }
            EpochDispersion::Start(span) => {
                let days = span * rng.uniform();
                sim.start = sim.start.add(seconds(days * 86_400.0)?);
                days
            }
        };

        // initial attitude (reference → body, scalar-first) and rate
        let (q0, w0) = scenario.initial;
        let (q, offset) = match self.attitude {
            AttitudeDispersion::Gaussian(sigma) => {
                let axis = random_unit(&mut rng);
                let angle = sigma * rng.normal();
                (compose(&axis_angle(&axis, angle), &q0), angle.abs())
            }
            AttitudeDispersion::Uniform => {
                let q = random_quaternion(&mut rng);
                (q, angle_between(&q, &q0))
            }
        };
        let w = match self.rate {
            RateDispersion::Added(sigma) => {
                w0 + Vec3d::new(rng.normal(), rng.normal(), rng.normal()) * sigma
            }
            RateDispersion::RandomDirection(frac) => {
                random_unit(&mut rng) * w0.norm() * (1.0 + frac * (2.0 * rng.uniform() - 1.0))
            }
        };
        scenario.initial = (q, w);
        let sim = &mut scenario.sim;

        // inertia: I' = R D½ I D½ Rᵀ (D the moments' scales, R the axes' turn)
        let scales = Vec3d::new(
            1.0 + self.inertia_moments * (2.0 * rng.uniform() - 1.0),
            1.0 + self.inertia_moments * (2.0 * rng.uniform() - 1.0),
            1.0 + self.inertia_moments * (2.0 * rng.uniform() - 1.0),
        );
        let tilt = Vec3d::new(rng.normal(), rng.normal(), rng.normal()) * self.inertia_axes_rad;
        let r = small_rotation(&tilt);
        let d = Mat3d::from_diagonal(&scales.map(f64::sqrt));
        sim.inertia = r * d * sim.inertia * d * r.transpose();

        // centre of mass: the centre of pressure moves the other way
        let com = Vec3d::new(rng.normal(), rng.normal(), rng.normal()) * self.com_offset_m;
        sim.disturbances.cp_body_m -= com;
        let dipole =
            Vec3d::new(rng.normal(), rng.normal(), rng.normal()) * self.residual_dipole_am2;
        sim.disturbances.residual_dipole_am2 = dipole;

        let (lo, hi) = self.density_factor;
        let density = lo * (hi / lo).powf(rng.uniform());
        sim.disturbances.density_factor = density;

        // actuators: each wheel's axis and momentum scale, each coil's axis
        let mut worst_scale = 0.0f64;
        sim.wheel_axes_body = sim
            .tiles
            .iter()
            .map(|t| {
                let tilt =
                    Vec3d::new(rng.normal(), rng.normal(), rng.normal()) * self.wheel_axis_rad;
                let scale = self.wheel_scale * rng.normal();
                worst_scale = worst_scale.max(scale.abs());
                small_rotation(&tilt) * t.normal_body().cast::<f64>() * (1.0 + scale)
            })
            .collect();
        for (axis, _) in &mut sim.coils {
            let tilt = Vec3d::new(rng.normal(), rng.normal(), rng.normal()) * self.coil_axis_rad;
            *axis = small_rotation(&tilt) * *axis;
        }

        Ok([
            offset.to_degrees(),
            w.norm().to_degrees(),
            scales.x,
            scales.y,
            scales.z,
            tilt_angle(&r).to_degrees(),
            com.norm() * 1e3,
            dipole.norm(),
            days,
            density,
            worst_scale,
        ])
    }
}

/// Turns the scenario's inertial attitudes (initial, target, commanded) with the reference frame
/// turned by `angle_rad` about the TEME z axis: `A' = A · A3(angle)`, so that each attitude keeps
/// its place relative to an orbit and a mean Sun that turned by that angle.
fn turn_reference(scenario: &mut Scenario, angle_rad: f64) {
    let turn = axis_angle(&Vec3d::z(), angle_rad);
    let turned = |q: &[f64; 4]| compose(q, &turn);
    let f32_turned = |q: &Quaternion| {
        let t = turned(&[
            f64::from(q.q0),
            f64::from(q.q1),
            f64::from(q.q2),
            f64::from(q.q3),
        ]);
        Quaternion {
            q0: t[0] as f32,
            q1: t[1] as f32,
            q2: t[2] as f32,
            q3: t[3] as f32,
        }
    };
    scenario.initial.0 = turned(&scenario.initial.0);
    scenario.target = scenario.target.map(|q| turned(&q));
    for (_, c) in &mut scenario.commands {
        match c {
            Command::Track { target } => *target = f32_turned(target),
            Command::Slew { target, .. } => {
                *target = f32_turned(&target.to_quaternion()).to_dcm();
            }
            Command::SunSafe => {}
        }
    }
}

fn seconds(s: f64) -> Result<TimeSpan, SimError> {
    TimeSpan::from_seconds_f64(s).map_err(|e| SimError::Model(e.to_string()))
}

/// The TLE epoch `(yy, day of year with fraction)` of `t`.
fn tle_epoch(t: &Epoch<Utc>) -> Result<(u8, f64), SimError> {
    let c = t.to_calendar();
    let jan1 = scenarios::epoch(c.year, 1, 1, 0)?;
    let day = 1.0 + t.span_since(&jan1).as_seconds_f64() / 86_400.0;
    Ok(((c.year.rem_euclid(100)) as u8, day))
}

/// A uniformly random unit vector.
fn random_unit(rng: &mut Rng) -> Vec3d {
    loop {
        let v = Vec3d::new(rng.normal(), rng.normal(), rng.normal());
        let n = v.norm();
        if n > 1e-9 {
            return v / n;
        }
    }
}

/// A uniformly random rotation (scalar-first unit quaternion: a normalised 4-D Gaussian).
fn random_quaternion(rng: &mut Rng) -> [f64; 4] {
    loop {
        let q = [rng.normal(), rng.normal(), rng.normal(), rng.normal()];
        let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        if n > 1e-9 {
            return [q[0] / n, q[1] / n, q[2] / n, q[3] / n];
        }
    }
}

/// The quaternion of a turn by `angle` about the unit `axis` (scalar-first).
fn axis_angle(axis: &Vec3d, angle: f64) -> [f64; 4] {
    let (s, c) = (0.5 * angle).sin_cos();
    [c, axis.x * s, axis.y * s, axis.z * s]
}

/// `A(p ⊗ q) = A(p) A(q)`: the attitude `q` (reference → body) followed by the body-frame turn
/// `p` (scalar-first quaternions, seed 000 §5's product).
fn compose(p: &[f64; 4], q: &[f64; 4]) -> [f64; 4] {
    let [p0, p1, p2, p3] = *p;
    let [q0, q1, q2, q3] = *q;
    // Shuster's product: (p0 q0 − p·q, p0 q + q0 p − p × q)
    let r = [
        p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3,
        p0 * q1 + q0 * p1 - (p2 * q3 - p3 * q2),
        p0 * q2 + q0 * p2 - (p3 * q1 - p1 * q3),
        p0 * q3 + q0 * p3 - (p1 * q2 - p2 * q1),
    ];
    let n = r.iter().map(|x| x * x).sum::<f64>().sqrt();
    [r[0] / n, r[1] / n, r[2] / n, r[3] / n]
}

/// The rotation angle between two attitudes, rad.
fn angle_between(p: &[f64; 4], q: &[f64; 4]) -> f64 {
    let d = (p[0] * q[0] + p[1] * q[1] + p[2] * q[2] + p[3] * q[3])
        .abs()
        .min(1.0);
    2.0 * d.acos()
}

/// The rotation matrix of the rotation vector `v` (rad).
fn small_rotation(v: &Vec3d) -> Mat3d {
    let angle = v.norm();
    if angle < 1e-15 {
        return Mat3d::identity();
    }
    // the DCM of a turn about the axis, transposed: a rotation of vectors (not of frames)
    dcm_of(&axis_angle(&(v / angle), angle)).transpose()
}

/// The angle of a rotation matrix, rad.
fn tilt_angle(r: &Mat3d) -> f64 {
    ((r.trace() - 1.0) / 2.0).clamp(-1.0, 1.0).acos()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compose_is_the_dcm_product() {
        let mut rng = Rng::new(3);
        for _ in 0..20 {
            let p = random_quaternion(&mut rng);
            let q = random_quaternion(&mut rng);
            let a = dcm_of(&compose(&p, &q));
            let b = dcm_of(&p) * dcm_of(&q);
            assert!((a - b).abs().max() < 1e-12);
        }
    }

    #[test]
    fn attitude_offset_is_the_drawn_angle() {
        let mut rng = Rng::new(5);
        let q0 = random_quaternion(&mut rng);
        let axis = random_unit(&mut rng);
        let q = compose(&axis_angle(&axis, 0.1), &q0);
        assert!((angle_between(&q, &q0) - 0.1).abs() < 1e-12);
    }

    #[test]
    fn small_rotation_turns_vectors_about_the_axis() {
        let r = small_rotation(&Vec3d::new(0.0, 0.0, std::f64::consts::FRAC_PI_2));
        let v = r * Vec3d::x();
        assert!((v - Vec3d::y()).norm() < 1e-12, "{v}");
        assert!((tilt_angle(&r) - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    }
}
