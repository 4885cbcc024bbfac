//! The realistic truth's devices: the constant errors drawn for each sensor and actuator, the
//! read models, and the actuators' dynamics. The parameters are the tables of [`super`].
//!
//! # Random numbers
//! [`gauss`] and [`uniform`] are a counter-based generator: SplitMix64's finaliser over
//! `(seed, stream, a, b)`, so every draw is a pure function of the scenario's seed, what it is
//! for ([`Stream`]), and two indices (the device, the control step, a component). A device's
//! constant errors use its tile index; a reading's noise uses the step and the tile; nothing
//! depends on how many reads came before.
//!
//! # Sun sensor (pinhole over a position-sensitive detector)
//! In the sensor's frame (the tile frame rotated by its misalignment), a source in direction
//! `d̂` (`d_z > 0`) puts its light at `(d_x/d_z, d_y/d_z)` × the pinhole's height on the
//! detector, with the irradiance `E cos θ`; the detector reports the irradiance-weighted mean
//! position of everything within its field of view:
//!
//! `(u, v) = (W☉ (u☉, v☉) + Σᵢ wᵢ cos θᵢ (uᵢ, vᵢ)) / W`, `W = W☉ + Σᵢ wᵢ cos θᵢ`,
//!
//! with the Sun (`W☉ = f☉ cos θ☉ × visible part of the spot`, `f☉` the visible fraction of the
//! solar disc) and the albedo points `wᵢ` ([`super::field::albedo_cap`]). Near the edge of the
//! field of view the spot (angular radius ρ) is cut by the detector's edge at `x = (FOV − θ)/ρ`
//! spot radii from its centre: the visible part is `1 − f`, `f = (acos x − x√(1−x²))/π`, and
//! its centroid moves inward by `f y_c / (1 − f)` radii (`y_c = ⅔ (1−x²)^{3/2} /
//! (acos x − x√(1−x²))`, the cut segment's centroid). No reading when `W` is below the
//! threshold. The angles are those of `(u, v, 1)`: `a = atan v`, `b = atan2(u, √(1+v²))`, plus
//! the calibration residual `δ = √2 r sin(k_a a + k_b b + φ)` (drawn `k` in ±[1, 3] rad⁻¹, φ) and
//! the noise `σ₀ / W` (σ₀ at normal incidence: the noise of a centroid grows as the signal falls).
//!
//! # Magnetometer
//! `y = diag(1 + s) [x̂′ ŷ′]ᵀ A_tile B_body + o + n`, with `x̂′`, `ŷ′` the tile's x and y rotated
//! by the misalignment and `ŷ′` tilted toward `x̂′` by the non-orthogonality; `B_body` includes
//! the spacecraft's field ([`super::field::Magnetics`]). Saturated beyond the range.
//!
//! # Gyro
//! `y = (1 + s) ĝ·ω̄ + b₀ + b(t) + n`, `ĝ` the tile normal tilted by the misalignment, `ω̄` the
//! mean body rate of the previous control period (the tile averages its samples), `b(t)` a
//! first-order Gauss–Markov bias (`b ← b e^{−Δt/τ} + σ √(1 − e^{−2Δt/τ}) n` each step), `n` of
//! 1σ `ARW/√T` (`T` the period).
//!
//! # Wheel
//! `ḣ = sat(k (h_set − h), ±τ_max) − τ_c sgn ω − c ω`, `k = 1/τ_loop`, `h = I_w ω`, `|ω| ≤
//! ω_max`: solved exactly where it is linear (within the torque limit, one direction of
//! rotation), stepped at ≤ 20 ms elsewhere; the body receives `−ḣ`. The set-point is rounded to the
//! set-point quantum; the read-back is `h` rounded to the read-back quantum. A wheel whose
//! motor torque cannot beat its Coulomb friction stays stopped.
//!
//! # Coil
//! `m = (1 + s) · round(m_cmd / q) q`, at most the current limit × turns × area; the current
//! follows its target with the time constant τ = L/R: `m(t) = m∞ + (m₀ − m∞) e^{−t/τ}`, and its
//! mean over an integration step is taken exactly.

use std::f64::consts::PI;

use super::field::{small_rotation, Magnetics};
use super::{CoilModel, GyroModel, MagnetometerModel, SunSensorModel, WheelModel};
use crate::linalg::{Mat3d, Vec3d};
use crate::tiles::Tile;

/// What a random draw is for (the generator's stream).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stream {
    /// Unmodelled field: source positions.
    FieldPosition = 1,
    /// Unmodelled field: source moments.
    FieldMoment,
    /// Residual dipole left by the calibration.
    ResidualDipole,
    /// Sun sensor misalignment.
    SunMisalignment,
    /// Sun sensor calibration residual.
    SunCalibration,
    /// Sun sensor noise.
    SunNoise,
    /// Magnetometer misalignment.
    MagMisalignment,
    /// Magnetometer scale factor, non-orthogonality and offset.
    MagConstants,
    /// Magnetometer noise.
    MagNoise,
    /// Gyro misalignment, scale factor, turn-on bias.
    GyroConstants,
    /// Gyro bias instability.
    GyroMarkov,
    /// Gyro noise.
    GyroNoise,
    /// Coil scale factor.
    CoilScale,
    /// Read time-outs.
    Dropout,
}

/// SplitMix64's finaliser.
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

fn hash(seed: u64, stream: Stream, a: u64, b: u64) -> u64 {
    mix(mix(mix(mix(seed) ^ stream as u64) ^ a) ^ b)
}

/// Uniform in (0, 1), a pure function of its arguments.
pub fn uniform(seed: u64, stream: Stream, a: u64, b: u64) -> f64 {
    ((hash(seed, stream, a, b) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
}

/// Standard normal, a pure function of its arguments (Box–Muller on two uniform draws).
pub fn gauss(seed: u64, stream: Stream, a: u64, b: u64) -> f64 {
    let u1 = uniform(seed, stream, a, 2 * b);
    let u2 = uniform(seed, stream, a, 2 * b + 1);
    (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
}

/// Three independent normals scaled by `sigma`.
fn gauss3(seed: u64, stream: Stream, a: u64, first: u64, sigma: f64) -> Vec3d {
    Vec3d::new(
        sigma * gauss(seed, stream, a, first),
        sigma * gauss(seed, stream, a, first + 1),
        sigma * gauss(seed, stream, a, first + 2),
    )
}

/// `A_tile` (body → tile) in f64.
fn body_to_tile(tile: &Tile) -> Mat3d {
    tile.body_to_tile.matrix().cast::<f64>()
}

/// A tile's Sun sensor: its frame and calibration residual (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct SunSensor {
    /// Body → sensor frame (the tile frame rotated by the misalignment).
    pub body_to_sensor: Mat3d,
    /// Calibration residual of `a` and `b`: amplitude, `k_a`, `k_b`, phase.
    calibration: [[f64; 4]; 2],
}

impl SunSensor {
    /// The sensor of tile `index`, its errors drawn from `seed`.
    pub fn new(model: &SunSensorModel, tile: &Tile, index: u64, seed: u64) -> Self {
        let mis = small_rotation(&gauss3(
            seed,
            Stream::SunMisalignment,
            index,
            0,
            model.misalignment_rad,
        ));
        let mut calibration = [[0.0; 4]; 2];
        for (k, c) in calibration.iter_mut().enumerate() {
            let draw = |j: u64| uniform(seed, Stream::SunCalibration, index, 4 * k as u64 + j);
            let wavenumber = |u: f64| {
                let m = 1.0 + 2.0 * u;
                if u < 0.5 {
                    -m
                } else {
                    m
                }
            };
            *c = [
                model.calibration_rad * 2f64.sqrt(),
                wavenumber(draw(0)),
                wavenumber(draw(1)),
                2.0 * PI * draw(2),
            ];
        }
        Self {
            body_to_sensor: mis * body_to_tile(tile),
            calibration,
        }
    }

    /// The calibration residual of angle `k` (0: `a`, 1: `b`) at `(a, b)`, rad.
    pub fn calibration_rad(&self, k: usize, a: f64, b: f64) -> f64 {
        let [amp, ka, kb, phase] = self.calibration[k.min(1)];
        amp * (ka * a + kb * b + phase).sin()
    }

    /// The angles `(a, b)` (rad) the sensor reports, or `None` below the threshold:
    /// `sun_body` the unit Sun direction, `sun_fraction` the visible part of the solar disc,
    /// `albedo_body` the albedo points in body axes, `noise` two standard normals.
    pub fn read(
        &self,
        model: &SunSensorModel,
        sun_body: &Vec3d,
        sun_fraction: f64,
        albedo_body: &[(Vec3d, f64)],
        noise: (f64, f64),
    ) -> Option<(f64, f64)> {
        let s = self.body_to_sensor * sun_body;
        let (mut w_sun, mut u_sun, mut v_sun) = (0.0, 0.0, 0.0);
        if sun_fraction > 0.0 && s.z > 0.0 {
            let theta = s.z.clamp(-1.0, 1.0).acos();
            let x = if model.spot_radius_rad > 0.0 {
                (model.fov_rad - theta) / model.spot_radius_rad
            } else if theta <= model.fov_rad {
                1.0
            } else {
                -1.0
            };
            if x > -1.0 {
                let (visible, inward) = if x >= 1.0 { (1.0, 0.0) } else { spot_clip(x) };
                let measured = (theta - inward * model.spot_radius_rad).max(0.0);
                let azimuth = s.y.atan2(s.x);
                let t = measured.tan();
                w_sun = sun_fraction * s.z * visible;
                u_sun = t * azimuth.cos();
                v_sun = t * azimuth.sin();
            }
        }
        let cos_fov = model.fov_rad.cos();
        let (mut w_alb, mut u_alb, mut v_alb) = (0.0, 0.0, 0.0);
        for (d, w) in albedo_body {
            let e = self.body_to_sensor * d;
            if e.z > cos_fov && e.z > 0.0 {
                let c = w * e.z;
                w_alb += c;
                u_alb += c * e.x / e.z;
                v_alb += c * e.y / e.z;
            }
        }
        let total = w_sun + w_alb;
        if total < model.threshold || total <= 0.0 {
            return None;
        }
        let u = (w_sun * u_sun + u_alb) / total;
        let v = (w_sun * v_sun + v_alb) / total;
        let a0 = v.atan();
        let b0 = u.atan2((1.0 + v * v).sqrt());
        let sigma = model.noise_rad / total;
        let a = a0 + self.calibration_rad(0, a0, b0) + sigma * noise.0;
        let b = b0 + self.calibration_rad(1, a0, b0) + sigma * noise.1;
        Some((a, b))
    }
}

/// A spot cut by an edge `x` spot radii from its centre (`−1 < x < 1`, positive inside): the
/// visible fraction and how far (spot radii) the visible part's centroid moves inward.
pub fn spot_clip(x: f64) -> (f64, f64) {
    let x = x.clamp(-1.0, 1.0);
    let root = (1.0 - x * x).max(0.0).sqrt();
    let segment = x.acos() - x * root;
    let outside = segment / PI;
    let visible = 1.0 - outside;
    if segment <= 0.0 || visible <= 1e-12 {
        return (visible.max(0.0), 0.0);
    }
    let centroid = 2.0 / 3.0 * root * root * root / segment;
    (visible, outside * centroid / visible)
}

/// A tile's magnetometer: its measuring axes in body axes (misalignment, non-orthogonality and
/// scale factor included) and its offset.
#[derive(Clone, Debug)]
pub struct Magnetometer {
    /// The two measuring axes (× 1 + scale factor), body.
    pub axes_body: [Vec3d; 2],
    /// Offset, nT.
    pub offset_nt: [f64; 2],
}

impl Magnetometer {
    /// The magnetometer of tile `index`, its errors drawn from `seed`.
    pub fn new(model: &MagnetometerModel, tile: &Tile, index: u64, seed: u64) -> Self {
        let mis = small_rotation(&gauss3(
            seed,
            Stream::MagMisalignment,
            index,
            0,
            model.misalignment_rad,
        ));
        let g = |k: u64| gauss(seed, Stream::MagConstants, index, k);
        let gamma = model.non_orthogonality_rad * g(0);
        let x_tile = mis * Vec3d::x() * (1.0 + model.scale_factor * g(1));
        let y_tile =
            mis * Vec3d::new(-gamma.sin(), gamma.cos(), 0.0) * (1.0 + model.scale_factor * g(2));
        let to_body = body_to_tile(tile).transpose();
        Self {
            axes_body: [to_body * x_tile, to_body * y_tile],
            offset_nt: [model.offset_nt * g(3), model.offset_nt * g(4)],
        }
    }

    /// The reading (nT, before quantisation) of the field `b_body_nt` with two standard normals
    /// of noise.
    pub fn read(
        &self,
        model: &MagnetometerModel,
        b_body_nt: &Vec3d,
        noise: (f64, f64),
    ) -> [f64; 2] {
        [
            self.axes_body[0].dot(b_body_nt) + self.offset_nt[0] + model.noise_nt * noise.0,
            self.axes_body[1].dot(b_body_nt) + self.offset_nt[1] + model.noise_nt * noise.1,
        ]
    }
}

/// A tile's gyro: its sensitive axis (× 1 + scale factor), body, and its turn-on bias.
#[derive(Clone, Debug)]
pub struct Gyro {
    /// Sensitive axis × (1 + scale factor), body.
    pub axis_body: Vec3d,
    /// Turn-on bias, rad/s.
    pub bias_radps: f64,
}

impl Gyro {
    /// The gyro of tile `index`, its errors drawn from `seed`.
    pub fn new(model: &GyroModel, tile: &Tile, index: u64, seed: u64) -> Self {
        let mis = small_rotation(&gauss3(
            seed,
            Stream::GyroConstants,
            index,
            0,
            model.misalignment_rad,
        ));
        let g = |k: u64| gauss(seed, Stream::GyroConstants, index, k);
        let axis_tile = mis * Vec3d::z() * (1.0 + model.scale_factor * g(3));
        Self {
            axis_body: body_to_tile(tile).transpose() * axis_tile,
            bias_radps: model.turn_on_bias_radps * g(4),
        }
    }
}

/// A reaction wheel's state.
#[derive(Clone, Debug)]
pub struct WheelState {
    /// Momentum along the spin axis, kg·m²/s.
    pub h_nms: f64,
    /// Rotor angle, rad.
    pub angle_rad: f64,
    /// Set-point in force, kg·m²/s.
    pub setpoint_nms: f64,
    /// Set-point commanded this step, taking effect at the actuation instant.
    pub pending_nms: Option<f64>,
    /// Rotor inertia, kg·m².
    pub inertia_kgm2: f64,
}

impl WheelState {
    /// A wheel at rest whose full speed holds `h_max_nms`.
    pub fn new(model: &WheelModel, h_max_nms: f64) -> Self {
        let inertia = if model.speed_limit_radps > 0.0 && h_max_nms > 0.0 {
            h_max_nms / model.speed_limit_radps
        } else {
            1.0
        };
        Self {
            h_nms: 0.0,
            angle_rad: 0.0,
            setpoint_nms: 0.0,
            pending_nms: None,
            inertia_kgm2: inertia,
        }
    }

    /// The set-point a command becomes (the speed quantum).
    pub fn quantised(&self, model: &WheelModel, h_nms: f64) -> f64 {
        let q = model.setpoint_lsb_radps * self.inertia_kgm2;
        if q > 0.0 {
            (h_nms / q).round() * q
        } else {
            h_nms
        }
    }

    /// The momentum the tachometer reports, kg·m²/s.
    pub fn readback_nms(&self, model: &WheelModel) -> f64 {
        let q = model.readback_lsb_radps * self.inertia_kgm2;
        if q > 0.0 {
            (self.h_nms / q).round() * q
        } else {
            self.h_nms
        }
    }

    /// Advances the wheel by `dt_s` toward its set-point; returns the momentum change.
    ///
    /// Where the motor is within its torque limit at both ends of an interval and the rotor
    /// keeps its direction, the loop is linear (`ḣ = a − b h`) and the interval is taken in one
    /// exact step (the error decays monotonically, so it stays within the limit in between);
    /// elsewhere (torque-limited, through zero speed) the wheel is stepped at ≤ 20 ms.
    pub fn advance(&mut self, model: &WheelModel, dt_s: f64) -> f64 {
        let start = self.h_nms;
        let mut remaining = dt_s;
        while remaining > 1e-12 {
            if let Some(angle) = self.linear_step(model, remaining) {
                self.angle_rad += angle;
                break;
            }
            let h = remaining.min(0.02);
            self.euler_step(model, h);
            remaining -= h;
        }
        self.angle_rad = self.angle_rad.rem_euclid(2.0 * PI);
        self.h_nms - start
    }

    /// The exact step of `t` seconds of the linear regime, if the wheel stays in it: returns the
    /// rotor's turn, rad (the momentum updated).
    fn linear_step(&mut self, model: &WheelModel, t: f64) -> Option<f64> {
        let tau = model.time_constant_s;
        if tau <= 0.0 || self.h_nms == 0.0 {
            return None;
        }
        let limit = model.torque_limit_nm;
        let within = |h: f64| ((self.setpoint_nms - h) / tau).abs() <= limit;
        let sign = self.h_nms.signum();
        // ḣ = (s − h)/τ − τ_c sgn − c h / I = a − b h
        let b = 1.0 / tau + model.viscous_nm_per_radps / self.inertia_kgm2;
        let a = self.setpoint_nms / tau - model.coulomb_nm * sign;
        let end_of = |t: f64| a / b + (self.h_nms - a / b) * (-b * t).exp();
        let end = end_of(t);
        let h_max = model.speed_limit_radps * self.inertia_kgm2;
        if !within(self.h_nms) || !within(end) || end.signum() != sign || end.abs() > h_max {
            return None;
        }
        let integral = a / b * t + (self.h_nms - a / b) * (1.0 - (-b * t).exp()) / b;
        self.h_nms = end;
        Some(integral / self.inertia_kgm2)
    }

    /// One explicit step of `h` seconds (torque-limited, or through zero speed).
    fn euler_step(&mut self, model: &WheelModel, h: f64) {
        let error = self.setpoint_nms - self.h_nms;
        let motor = if model.time_constant_s > 0.0 {
            (error / model.time_constant_s).clamp(-model.torque_limit_nm, model.torque_limit_nm)
        } else {
            (error / h).clamp(-model.torque_limit_nm, model.torque_limit_nm)
        };
        let omega = self.h_nms / self.inertia_kgm2;
        let before = self.h_nms;
        let next = if omega == 0.0 {
            // static: the motor must beat the Coulomb friction
            if motor.abs() <= model.coulomb_nm {
                0.0
            } else {
                before + (motor - model.coulomb_nm * motor.signum()) * h
            }
        } else {
            let friction = model.coulomb_nm * omega.signum() + model.viscous_nm_per_radps * omega;
            let n = before + (motor - friction) * h;
            if n.signum() != before.signum() && motor.abs() <= model.coulomb_nm {
                // the friction stops it at zero
                0.0
            } else {
                n
            }
        };
        let h_max = model.speed_limit_radps * self.inertia_kgm2;
        self.h_nms = next.clamp(-h_max, h_max);
        self.angle_rad += 0.5 * (before + self.h_nms) / self.inertia_kgm2 * h;
    }
}

/// A coil's state.
#[derive(Clone, Debug)]
pub struct CoilState {
    /// Dipole now, A·m².
    pub m_am2: f64,
    /// Dipole the current tends to, A·m².
    pub target_am2: f64,
    /// Target commanded this step, taking effect at the actuation instant.
    pub pending_am2: Option<f64>,
    /// 1 + scale-factor error.
    pub gain: f64,
}

impl CoilState {
    /// A coil at rest, its scale factor drawn from `seed`.
    pub fn new(model: &CoilModel, index: u64, seed: u64) -> Self {
        Self {
            m_am2: 0.0,
            target_am2: 0.0,
            pending_am2: None,
            gain: 1.0 + model.scale_factor * gauss(seed, Stream::CoilScale, index, 0),
        }
    }

    /// The dipole a command `m_am2` drives the coil to (quantisation, scale factor, current
    /// limit).
    pub fn target_of(&self, model: &CoilModel, m_am2: f64) -> f64 {
        let q = if model.lsb_am2 > 0.0 {
            (m_am2 / model.lsb_am2).round() * model.lsb_am2
        } else {
            m_am2
        };
        let limit = model.current_limit_a * model.am2_per_a;
        (q * self.gain).clamp(-limit, limit)
    }

    /// The dipole `dt_s` from now, A·m².
    pub fn at(&self, model: &CoilModel, dt_s: f64) -> f64 {
        if model.time_constant_s <= 0.0 {
            return self.target_am2;
        }
        self.target_am2 + (self.m_am2 - self.target_am2) * (-dt_s / model.time_constant_s).exp()
    }

    /// Advances the coil by `dt_s`; returns its mean dipole over the interval.
    pub fn advance(&mut self, model: &CoilModel, dt_s: f64) -> f64 {
        let tau = model.time_constant_s;
        let mean = if tau <= 0.0 || dt_s <= 0.0 {
            self.target_am2
        } else {
            self.target_am2
                + (self.m_am2 - self.target_am2) * tau / dt_s * (1.0 - (-dt_s / tau).exp())
        };
        self.m_am2 = self.at(model, dt_s);
        mean
    }

    /// The coil current now, A.
    pub fn current_a(&self, model: &CoilModel) -> f64 {
        if model.am2_per_a > 0.0 {
            self.m_am2 / model.am2_per_a
        } else {
            0.0
        }
    }
}

/// Where the loop is within a control step (the simulator infers it from the calls).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Before any read: commands take effect at once (the loop's coils-off).
    Start,
    /// The tiles have been read.
    Read,
    /// Actuator commands given: they take effect at the actuation instant.
    Actuate,
}

/// Everything the realistic truth keeps per simulator (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct Devices {
    /// Sun sensors, per tile.
    pub sun: Vec<Option<SunSensor>>,
    /// Magnetometers, per tile.
    pub magnetometer: Vec<Option<Magnetometer>>,
    /// Gyros, per tile.
    pub gyro: Vec<Option<Gyro>>,
    /// Gyro Gauss–Markov biases, per tile, rad/s.
    pub gyro_markov_radps: Vec<f64>,
    /// Wheels, per tile (unused where the tile has none).
    pub wheels: Vec<WheelState>,
    /// Coils.
    pub coils: Vec<CoilState>,
    /// The spacecraft's own fields.
    pub magnetics: Magnetics,
}
