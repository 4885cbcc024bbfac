//! The Earth's albedo as a Sun sensor sees it: the irradiance vector of the sunlit Earth at the
//! satellite, and the apparent Sun direction it makes on a centroiding sensor.
//!
//! # Model
//! The Earth is a sphere of radius [`EARTH_RADIUS_KM`] reflecting as a uniform Lambertian
//! surface of albedo `a` (Wertz, *Spacecraft Attitude Determination and Control*, 1978, §5.3:
//! Lambertian reflection; Bhanderi, *Spacecraft Attitude Determination with Earth Albedo
//! Corrected Sun Sensor Measurements*, 2005, ch. 3, for the irradiance at a satellite). A
//! ground point at solar zenith angle `ζ` has the radiance `a E☉ cos ζ / π`; seen from the
//! satellite in the direction `d̂` within the solid angle `dΩ` it adds `a cos ζ / π · dΩ · d̂`
//! to the irradiance vector `D` (in units of the solar irradiance `E☉`). The visible cap (the
//! cone of half angle `ρ`, `sin ρ = R⊕/r`, about nadir) is integrated on [`RINGS`] rings of
//! equal solid angle times [`SECTORS`] azimuths. A ring's nadir angle `η` fixes its ground
//! point's central angle from the sub-satellite point, `γ = asin(k) − η` with `k = r sin η /
//! R⊕`, so no ray is intersected with the sphere.
//!
//! # On a sensor
//! A centroiding sensor (a pinhole over a position-sensitive detector) reports the
//! irradiance-weighted mean of the positions `(d_x/d_z, d_y/d_z)` of its sources, each weighted
//! by its irradiance `E d_z`; the weighted sum is `(Σ E d_x, Σ E d_y)` over the total `Σ E d_z`:
//! the direction of the **vector sum** of the sources' irradiance vectors. With the Sun's
//! `f ŝ` (`f` its visible fraction) and the albedo's `D` over the points within the sensor's
//! field of view ([`FieldOfView`]; the attitude places it), the sensor measures
//! `normalise(f ŝ + D)` ([`apparent_sun`]). The filter pairs that with the sensors' direction
//! in place of `ŝ`.
//!
//! **Accuracy** (f32; `cargo test --test albedo -- --nocapture`, against a 160 000-point f64
//! integration of the same Earth, from the subsolar point to past the terminator at 400–800 km):
//! the whole cap's `D` within 0.27 % of the largest; the apparent Sun of a 0.30 albedo within
//! 0.031°; over a 70° field of view looking 45° off nadir within 0.41° (the 32 points resolve
//! the field's edge coarsely).

use crate::attitude::Quaternion;
use crate::env::eclipse::EARTH_RADIUS_KM;
use crate::fmath;
use crate::linalg::{cross, div, dot, lin3, norm, Vec3};
use crate::tiles::Tile;

/// Rings of equal solid angle of the quadrature.
pub const RINGS: usize = 4;
/// Azimuths of the quadrature on each ring.
pub const SECTORS: usize = 8;

/// `(cos, sin)` of the sectors' azimuths, `2π j / 8`.
const AZIMUTHS: [(f32, f32); SECTORS] = [
    (1.0, 0.0),
    (
        core::f32::consts::FRAC_1_SQRT_2,
        core::f32::consts::FRAC_1_SQRT_2,
    ),
    (0.0, 1.0),
    (
        -core::f32::consts::FRAC_1_SQRT_2,
        core::f32::consts::FRAC_1_SQRT_2,
    ),
    (-1.0, 0.0),
    (
        -core::f32::consts::FRAC_1_SQRT_2,
        -core::f32::consts::FRAC_1_SQRT_2,
    ),
    (0.0, -1.0),
    (
        core::f32::consts::FRAC_1_SQRT_2,
        -core::f32::consts::FRAC_1_SQRT_2,
    ),
];

/// A sensor's field of view: its boresight (unit, the frame of the inputs) and the cosine of its
/// half angle.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct FieldOfView {
    /// The boresight (the tile's outward normal), unit.
    pub boresight: Vec3,
    /// `cos` of the half angle.
    pub cos_half_angle: f32,
}

/// The albedo's irradiance vector `D` at the satellite, in units of the solar irradiance, in
/// the frame of the inputs (TEME): `r_km` the position, `sun` the unit Sun direction, `albedo`
/// the Earth's; only the points within `seen_by`'s field of view if one is given. `None` for a
/// position not above the surface or a non-finite input; zero over the night side.
#[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
pub fn irradiance(
    r_km: &Vec3,
    sun: &Vec3,
    albedo: f32,
    seen_by: Option<&FieldOfView>,
) -> Option<Vec3> {
    let r = norm(r_km);
    if !(r > EARTH_RADIUS_KM) || !r.is_finite() || !(albedo >= 0.0) {
        return None;
    }
    let up = div(r_km, r);
    // a basis about nadir: e1 ⟂ up, e2 = up × e1
    let helper = if !(up.x * up.x >= 0.5) {
        Vec3::x()
    } else {
        Vec3::y()
    };
    let e1 = cross(&up, &helper);
    let e1 = div(&e1, norm(&e1));
    let e2 = cross(&up, &e1);
    let (s_up, s1, s2) = (dot(&up, sun), dot(&e1, sun), dot(&e2, sun));
    // the boresight in the same basis, and the cosine it must reach (−2: every point)
    let (b_up, b1, b2, cos_fov) = match seen_by {
        Some(f) => (
            dot(&up, &f.boresight),
            dot(&e1, &f.boresight),
            dot(&e2, &f.boresight),
            f.cos_half_angle,
        ),
        None => (0.0, 0.0, 0.0, -2.0),
    };
    if !(s_up.is_finite() && s1.is_finite() && s2.is_finite()) {
        return None;
    }
    let ratio = EARTH_RADIUS_KM / r;
    let cos_rho = fmath::sqrt(1.0 - ratio * ratio);
    let ring_width = (1.0 - cos_rho) / RINGS as f32;
    // solid angle of one point over π, times the albedo
    let w = albedo * 2.0 * ring_width / SECTORS as f32;
    // D in the basis (−up, e1, e2): along nadir, and across it
    let (mut d_nadir, mut d1, mut d2) = (0.0f32, 0.0f32, 0.0f32);
    for i in 0..RINGS {
        let cos_eta = 1.0 - (i as f32 + 0.5) * ring_width;
        let sin_eta = fmath::sqrt(1.0 - cos_eta * cos_eta);
        // the ground point's central angle γ = asin(k) − η, k = r sin η / R⊕
        let k = fmath::min(sin_eta / ratio, 1.0);
        let c = fmath::sqrt(1.0 - k * k);
        let (cos_g, sin_g) = (c * cos_eta + k * sin_eta, k * cos_eta - c * sin_eta);
        // by reference: by value the table was copied to the stack at each ring
        for &(cos_p, sin_p) in &AZIMUTHS {
            // the ground point's normal is cos γ·up + sin γ·(cos ψ e1 + sin ψ e2)
            let cos_zeta = cos_g * s_up + sin_g * (cos_p * s1 + sin_p * s2);
            // d̂ = −cos η up + sin η (cos ψ e1 + sin ψ e2), against the boresight
            let cos_view = sin_eta * (cos_p * b1 + sin_p * b2) - cos_eta * b_up;
            if cos_zeta > 0.0 && cos_view >= cos_fov {
                let e = w * cos_zeta;
                d_nadir += e * cos_eta;
                d1 += e * sin_eta * cos_p;
                d2 += e * sin_eta * sin_p;
            }
        }
    }
    Some(lin3(&up, &e1, &e2, -d_nadir, d1, d2))
}

/// The albedo irradiance of a unit albedo (TEME, units of the solar irradiance) averaged over
/// the tiles whose working Sun sensor the Sun lights at `attitude` (reference TEME → body; lit:
/// the Sun within the field of view, `n̂ · ŝ ≥ cos_half_fov`), each over its own field of view
/// ([`irradiance`]): the albedo the averaged Sun sensors see
/// ([`crate::determination::sun_sensor::sun_direction_body`]). `None` if no sensor is lit or
/// the geometry is refused.
#[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
pub fn seen_by_lit_sensors(
    tiles: &[Tile],
    r_km: &Vec3,
    sun: &Vec3,
    attitude: &Quaternion,
    cos_half_fov: f32,
) -> Option<Vec3> {
    let a = attitude.to_dcm();
    let sun_body = a.to_body(sun);
    // element by element (`Vec3::zeros()` is a loop and a copy on the MSP430)
    let (mut sum, mut n) = (Vec3::new(0.0, 0.0, 0.0), 0.0f32);
    for tile in tiles.iter().filter(|t| t.has_working_sun_sensor()) {
        let normal = tile.normal_body_inline();
        if dot(&normal, &sun_body) >= cos_half_fov {
            let fov = FieldOfView {
                boresight: a.to_reference(&normal),
                cos_half_angle: cos_half_fov,
            };
            sum += irradiance(r_km, sun, 1.0, Some(&fov))?;
            n += 1.0;
        }
    }
    (n > 0.0).then(|| div(&sum, n))
}

/// The direction a centroiding Sun sensor measures (unit, the frame of the inputs): that of
/// `fraction · sun + albedo_irradiance` (see the [module docs](self)); `None` if it has no
/// length.
pub fn apparent_sun(sun: &Vec3, fraction: f32, albedo_irradiance: &Vec3) -> Option<Vec3> {
    let v = sun * fraction + albedo_irradiance;
    let n = norm(&v);
    (n > 0.0 && n.is_finite()).then(|| div(&v, n))
}
