//! The realistic truth's fields: the unmodelled part of the geomagnetic field, the spacecraft's
//! own fields at the magnetometers, and the Earth's albedo as a Sun sensor sees it.
//!
//! # Unmodelled field
//! `ΔB(r) = Σₖ μ₀/4π · (3 (mₖ·d̂) d̂ − mₖ) / d³`, `d = r − pₖ`: the potential field of
//! [`super::FieldTruth::sources`] dipoles `mₖ` at Earth-fixed points `pₖ`, uniform on a sphere of
//! radius [`super::FieldTruth::source_radius_re`] Earth radii, moments with independent Gaussian
//! components, all drawn from the scenario's seed; the moments are then scaled so that the RMS of
//! `|ΔB|` over the sphere of the orbit's radius (a 2 000-point Fibonacci lattice) is
//! [`super::FieldTruth::unmodelled_rms_nt`]. Outside its sources the field is curl- and
//! divergence-free, as the part of the real field a model leaves out is where the satellite
//! flies; it is fixed to the Earth, so the satellite meets it as a smooth function of time along
//! its orbit (sources at 0.6 R_E: ≥ 3 000 km from a 500 km orbit; along a day of the `tracking`
//! orbit its autocorrelation falls to one half in 280 s, `tests/truth.rs`).
//!
//! # Spacecraft fields
//! At each magnetometer (its tile's centre, `n̂ · half side`, plus its place on the tile):
//! - the residual dipole left by the ground calibration, a point dipole at the body centre;
//! - each coil, a square loop of `N` turns in its tile's plane, by Biot–Savart over its four
//!   sides (closed form for a straight segment: `B = μ₀I/4π · (û × r₁)/|û × r₁|² ·
//!   (û·r̂₁ − û·r̂₂)`), exact at any distance, unlike a dipole;
//! - each wheel's rotor, a transverse point dipole turning with the rotor.
//!
//! Each source is linear in its strength, so the field of each at each magnetometer is computed
//! once per unit strength ([`Magnetics::new`]) and scaled at each read.
//!
//! # Albedo
//! The Earth as a sphere of radius 6 378.137 km with a uniform Lambertian albedo `a`: a ground
//! point with solar zenith angle ζ has the radiance `a E☉ cos ζ / π` (0 on the night side). The
//! visible cap (angular radius `asin(R/r)` about the nadir) is split into 6 rings of equal solid
//! angle × 12 sectors; each point carries its direction from the satellite and its irradiance at
//! normal incidence in units of the solar irradiance, `a cos ζ / π · ΔΩ`. A sensor of normal
//! `n̂` then receives `Σ wᵢ max(n̂·d̂ᵢ, 0)` over the points in its field of view. For an
//! observer far away this is the Lambert-sphere law `a (2/3) (R/r)² Φ(α)`; at 500 km a
//! nadir-facing sensor receives 0.257 E☉ under a zenith Sun (the 72 points agree with 2 880 to
//! 0.01 %, `tests/truth.rs`).

use std::f64::consts::PI;

use super::devices::{gauss, Stream};
use super::{FieldTruth, SpacecraftMagnetics};
use crate::linalg::{Mat3d, Vec3d};
use crate::tiles::Tile;

/// μ₀ / 4π, T·m/A.
const MU0_4PI: f64 = 1e-7;

/// Earth's radius for the albedo sphere and the source sphere, m.
pub const EARTH_RADIUS_M: f64 = 6_378_137.0;

/// The field of a point dipole `m_am2` at `r_m` from it, T.
pub fn dipole_field_t(m_am2: &Vec3d, r_m: &Vec3d) -> Vec3d {
    let d = r_m.norm();
    if d < 1e-9 {
        return Vec3d::zeros();
    }
    let u = r_m / d;
    (u * (3.0 * m_am2.dot(&u)) - m_am2) * (MU0_4PI / (d * d * d))
}

/// The field at `p` of a straight segment from `a` to `b` carrying 1 A, T.
pub fn segment_field_t(a: &Vec3d, b: &Vec3d, p: &Vec3d) -> Vec3d {
    let ab = b - a;
    let len = ab.norm();
    if len < 1e-12 {
        return Vec3d::zeros();
    }
    let u = ab / len;
    let r1 = p - a;
    let r2 = p - b;
    let c = u.cross(&r1);
    let d2 = c.norm_squared();
    let (n1, n2) = (r1.norm(), r2.norm());
    if d2 < 1e-18 || n1 < 1e-12 || n2 < 1e-12 {
        return Vec3d::zeros();
    }
    c * (MU0_4PI / d2 * (u.dot(&r1) / n1 - u.dot(&r2) / n2))
}

/// The field at `p` of a square loop of side `side_m`, centred at `centre`, normal `normal`
/// (its dipole for a positive current), one turn carrying 1 A, T.
pub fn square_loop_field_t(centre: &Vec3d, normal: &Vec3d, side_m: f64, p: &Vec3d) -> Vec3d {
    let n = normal.normalize();
    let helper = if n.x.abs() < 0.9 {
        Vec3d::x()
    } else {
        Vec3d::y()
    };
    let e1 = n.cross(&helper).normalize();
    let e2 = n.cross(&e1);
    let h = 0.5 * side_m;
    // counter-clockwise about n: e1 then e2 (e1 × e2 = n)
    let corners = [
        centre + (-e1 - e2) * h,
        centre + (e1 - e2) * h,
        centre + (e1 + e2) * h,
        centre + (-e1 + e2) * h,
    ];
    (0..4).fold(Vec3d::zeros(), |acc, k| {
        acc + segment_field_t(&corners[k], &corners[(k + 1) % 4], p)
    })
}

/// A unit vector uniform on the sphere from three Gaussian draws.
fn unit_vector(seed: u64, stream: Stream, index: u64) -> Vec3d {
    let v = Vec3d::new(
        gauss(seed, stream, index, 0),
        gauss(seed, stream, index, 1),
        gauss(seed, stream, index, 2),
    );
    let n = v.norm();
    // a zero draw has probability zero; z keeps it a pure function of the seed
    if n > 1e-6 {
        v / n
    } else {
        Vec3d::z()
    }
}

/// The `k`-th of `n` points of a Fibonacci lattice on the unit sphere.
fn fibonacci_point(k: usize, n: usize) -> Vec3d {
    let golden = PI * (3.0 - 5f64.sqrt());
    let z = 1.0 - (2.0 * k as f64 + 1.0) / n as f64;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = golden * k as f64;
    Vec3d::new(r * phi.cos(), r * phi.sin(), z)
}

/// The unmodelled part of the geomagnetic field (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct UnmodelledField {
    /// Source positions, Earth-fixed, m.
    positions: Vec<Vec3d>,
    /// Source moments, Earth-fixed, A·m².
    moments: Vec<Vec3d>,
}

impl UnmodelledField {
    /// The field of `config` drawn from `seed`, scaled to its RMS on the sphere of radius
    /// `orbit_radius_m`.
    pub fn new(config: &FieldTruth, seed: u64, orbit_radius_m: f64) -> Self {
        let mut field = Self {
            positions: Vec::new(),
            moments: Vec::new(),
        };
        if config.unmodelled_rms_nt <= 0.0 || config.sources == 0 {
            return field;
        }
        let radius = config.source_radius_re * EARTH_RADIUS_M;
        for k in 0..config.sources as u64 {
            field
                .positions
                .push(unit_vector(seed, Stream::FieldPosition, k) * radius);
            field.moments.push(Vec3d::new(
                gauss(seed, Stream::FieldMoment, k, 0),
                gauss(seed, Stream::FieldMoment, k, 1),
                gauss(seed, Stream::FieldMoment, k, 2),
            ));
        }
        let rms = field.rms_on_sphere_nt(orbit_radius_m, 2000);
        if rms > 0.0 {
            let scale = config.unmodelled_rms_nt / rms;
            for m in &mut field.moments {
                *m *= scale;
            }
        }
        field
    }

    /// The field at the Earth-fixed position `r_m` (m), Earth-fixed components, nT.
    pub fn ecef_nt(&self, r_m: &Vec3d) -> Vec3d {
        self.positions
            .iter()
            .zip(self.moments.iter())
            .fold(Vec3d::zeros(), |acc, (p, m)| {
                acc + dipole_field_t(m, &(r_m - p))
            })
            * 1e9
    }

    /// The RMS of `|ΔB|` over `points` points of a Fibonacci lattice on the sphere of radius
    /// `radius_m`, nT.
    pub fn rms_on_sphere_nt(&self, radius_m: f64, points: usize) -> f64 {
        if points == 0 {
            return 0.0;
        }
        let sum: f64 = (0..points)
            .map(|k| {
                self.ecef_nt(&(fibonacci_point(k, points) * radius_m))
                    .norm_squared()
            })
            .sum();
        (sum / points as f64).sqrt()
    }
}

/// The spacecraft's own fields at each tile's magnetometer, per unit strength of each source
/// (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct Magnetics {
    /// Magnetometer positions, body, m (`None`: the tile has none).
    pub magnetometer_m: Vec<Option<Vec3d>>,
    /// The residual dipole not removed by the calibration, body, A·m².
    pub residual_dipole_am2: Vec3d,
    /// Field of each coil per ampere at each magnetometer, body, T/A: `[coil][tile]`.
    coil_t_per_a: Vec<Vec<Vec3d>>,
    /// The tile each coil lies in (`None`: at the body centre, as a point dipole).
    pub coil_tile: Vec<Option<usize>>,
    /// Field of each tile's rotor dipole at each magnetometer, body, T, for the rotor along the
    /// wheel tile's x and y axes: `[wheel tile][magnetometer tile]`.
    rotor_t: Vec<Vec<(Vec3d, Vec3d)>>,
}

impl Magnetics {
    /// The geometry of `tiles` and `coils` (body axis each) with the parameters of `config`; the
    /// residual dipole error drawn from `seed`.
    pub fn new(
        config: &SpacecraftMagnetics,
        tiles: &[Tile],
        coils: &[(Vec3d, f64)],
        seed: u64,
    ) -> Self {
        let frame = |t: &Tile| -> (Vec3d, Vec3d, Vec3d) {
            (
                t.x_body().cast::<f64>(),
                t.y_body().cast::<f64>(),
                t.normal_body().cast::<f64>(),
            )
        };
        let on_tile = |t: &Tile, p: &[f64; 3]| -> Vec3d {
            let (x, y, z) = frame(t);
            z * config.half_side_m + x * p[0] + y * p[1] + z * p[2]
        };
        let magnetometer_m: Vec<Option<Vec3d>> = tiles
            .iter()
            .map(|t| {
                t.equipment
                    .magnetometer
                    .then(|| on_tile(t, &config.magnetometer_on_tile_m))
            })
            .collect();
        let s = config.residual_dipole_error_am2;
        let residual_dipole_am2 = Vec3d::new(
            s * gauss(seed, Stream::ResidualDipole, 0, 0),
            s * gauss(seed, Stream::ResidualDipole, 0, 1),
            s * gauss(seed, Stream::ResidualDipole, 0, 2),
        );
        let coil_tile: Vec<Option<usize>> = coils
            .iter()
            .map(|(axis, _)| {
                tiles.iter().position(|t| {
                    t.equipment.magnetometer
                        && t.normal_body().cast::<f64>().dot(&axis.normalize()).abs() > 0.99
                })
            })
            .collect();
        let coil_t_per_a = coils
            .iter()
            .zip(coil_tile.iter())
            .map(|((axis, _), host)| {
                let axis = axis.normalize();
                magnetometer_m
                    .iter()
                    .map(|p| match (p, host) {
                        (Some(p), Some(h)) => {
                            let centre = frame(&tiles[*h]).2 * config.half_side_m;
                            square_loop_field_t(&centre, &axis, config.coil_side_m, p)
                                * config.coil_turns
                        }
                        (Some(p), None) => {
                            let m = axis * (config.coil_turns * config.coil_side_m.powi(2));
                            dipole_field_t(&m, p)
                        }
                        (None, _) => Vec3d::zeros(),
                    })
                    .collect()
            })
            .collect();
        let rotor_t = tiles
            .iter()
            .map(|t| {
                if !t.equipment.reaction_wheel || config.rotor_dipole_am2 == 0.0 {
                    return vec![(Vec3d::zeros(), Vec3d::zeros()); tiles.len()];
                }
                let (x, y, _) = frame(t);
                let at = on_tile(t, &config.rotor_on_tile_m);
                magnetometer_m
                    .iter()
                    .map(|p| match p {
                        Some(p) => (
                            dipole_field_t(&(x * config.rotor_dipole_am2), &(p - at)),
                            dipole_field_t(&(y * config.rotor_dipole_am2), &(p - at)),
                        ),
                        None => (Vec3d::zeros(), Vec3d::zeros()),
                    })
                    .collect()
            })
            .collect();
        Self {
            magnetometer_m,
            residual_dipole_am2,
            coil_t_per_a,
            coil_tile,
            rotor_t,
        }
    }

    /// The spacecraft's field at tile `tile`'s magnetometer, body, nT: coil currents in A (one
    /// per coil), rotor angles in rad (one per tile; those without a wheel are ignored).
    pub fn at_magnetometer_nt(&self, tile: usize, coil_a: &[f64], rotor_rad: &[f64]) -> Vec3d {
        let Some(Some(p)) = self.magnetometer_m.get(tile) else {
            return Vec3d::zeros();
        };
        let mut b = dipole_field_t(&self.residual_dipole_am2, p);
        for (gains, i) in self.coil_t_per_a.iter().zip(coil_a.iter()) {
            if let Some(g) = gains.get(tile) {
                b += g * *i;
            }
        }
        for (fields, angle) in self.rotor_t.iter().zip(rotor_rad.iter()) {
            if let Some((gx, gy)) = fields.get(tile) {
                b += gx * angle.cos() + gy * angle.sin();
            }
        }
        b * 1e9
    }

    /// The field of coil `coil` at tile `tile`'s magnetometer per ampere, body, T/A.
    pub fn coil_field_t_per_a(&self, coil: usize, tile: usize) -> Vec3d {
        self.coil_t_per_a
            .get(coil)
            .and_then(|g| g.get(tile))
            .copied()
            .unwrap_or_else(Vec3d::zeros)
    }
}

/// The albedo's quadrature points: direction from the satellite (unit, the frame of the inputs)
/// and irradiance at normal incidence in units of the solar irradiance (see the
/// [module docs](self)); night-side points are left out.
pub fn albedo_cap(
    r_km: &Vec3d,
    sun: &Vec3d,
    albedo: f64,
    rings: usize,
    sectors: usize,
) -> Vec<(Vec3d, f64)> {
    let mut out = Vec::new();
    let r = r_km.norm() * 1e3;
    if albedo <= 0.0 || r <= EARTH_RADIUS_M || rings == 0 || sectors == 0 {
        return out;
    }
    let sun = sun.normalize();
    let nadir = -r_km / r_km.norm();
    let helper = if nadir.x.abs() < 0.9 {
        Vec3d::x()
    } else {
        Vec3d::y()
    };
    let e1 = nadir.cross(&helper).normalize();
    let e2 = nadir.cross(&e1);
    let cos_rho = (1.0 - (EARTH_RADIUS_M / r).powi(2)).sqrt();
    let d_omega = 2.0 * PI * (1.0 - cos_rho) / (rings * sectors) as f64;
    let position = nadir * -r;
    let azimuths: Vec<(f64, f64)> = (0..sectors)
        .map(|j| (2.0 * PI * (j as f64 + 0.5) / sectors as f64).sin_cos())
        .collect();
    for i in 0..rings {
        // rings of equal solid angle; the point at the ring's middle in solid angle
        let cos_eta = 1.0 - (i as f64 + 0.5) / rings as f64 * (1.0 - cos_rho);
        let sin_eta = (1.0 - cos_eta * cos_eta).max(0.0).sqrt();
        for (sin_psi, cos_psi) in &azimuths {
            let d = nadir * cos_eta + (e1 * *cos_psi + e2 * *sin_psi) * sin_eta;
            // nearest intersection with the sphere
            let b = position.dot(&d);
            let disc = b * b - (position.norm_squared() - EARTH_RADIUS_M * EARTH_RADIUS_M);
            if disc < 0.0 {
                continue;
            }
            let t = -b - disc.sqrt();
            let ground = (position + d * t) / EARTH_RADIUS_M;
            let cos_zeta = ground.dot(&sun);
            if cos_zeta > 0.0 {
                out.push((d, albedo * cos_zeta / PI * d_omega));
            }
        }
    }
    out
}

/// Rotation by the small angles `(x, y, z)` (rad) about the axes: `exp([θ]×)` (Rodrigues).
pub fn small_rotation(theta: &Vec3d) -> Mat3d {
    let angle = theta.norm();
    if angle < 1e-15 {
        return Mat3d::identity();
    }
    let k = theta / angle;
    let kx = Mat3d::new(0.0, -k.z, k.y, k.z, 0.0, -k.x, -k.y, k.x, 0.0);
    Mat3d::identity() + kx * angle.sin() + kx * kx * (1.0 - angle.cos())
}
