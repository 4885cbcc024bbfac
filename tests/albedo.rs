//! The on-board albedo model (`acs::env::albedo`, 4 rings × 8 azimuths, f32) against a dense
//! f64 integration of the same Lambertian Earth (the simulator's truth quadrature,
//! `host::sim::realistic::field::albedo_cap`, 400 rings × 400 azimuths): the irradiance vector
//! of the whole cap and of a sensor's field of view, and the apparent Sun it makes, over
//! positions from the subsolar point to the terminator at 400–800 km.
//! `cargo test --test albedo -- --nocapture` prints the measured errors.

use acs::env::albedo::{apparent_sun, irradiance, seen_by_lit_sensors, FieldOfView};
use acs::host::sim::realistic::field::albedo_cap;
use acs::linalg::{Vec3, Vec3d};

const RE_KM: f64 = 6378.137;

fn v32(v: &Vec3d) -> Vec3 {
    Vec3::new(v.x as f32, v.y as f32, v.z as f32)
}

fn v64(v: &Vec3) -> Vec3d {
    Vec3d::new(v.x as f64, v.y as f64, v.z as f64)
}

/// The dense integration over the points within `fov` (boresight, cos of the half angle).
fn dense(r_km: &Vec3d, sun: &Vec3d, fov: Option<(&Vec3d, f64)>) -> Vec3d {
    albedo_cap(r_km, sun, 1.0, 400, 400)
        .iter()
        .filter(|(d, _)| fov.is_none_or(|(b, c)| d.dot(b) >= c))
        .fold(Vec3d::zeros(), |acc, (d, w)| acc + d * *w)
}

/// Positions at `alt` km with the Sun `zenith_deg` from the local vertical.
fn geometry(alt_km: f64, zenith_deg: f64) -> (Vec3d, Vec3d) {
    let r = Vec3d::new(0.3, -0.4, 0.866).normalize() * (RE_KM + alt_km);
    let up = r.normalize();
    let side = up.cross(&Vec3d::new(1.0, 0.0, 0.0)).normalize();
    let z = zenith_deg.to_radians();
    (r, up * z.cos() + side * z.sin())
}

#[test]
fn against_a_dense_integration() {
    let (mut worst_rel, mut worst_dir_deg, mut worst_fov_deg) = (0.0f64, 0.0f64, 0.0f64);
    for alt in [400.0, 500.0, 800.0] {
        for zenith in [0.0, 30.0, 60.0, 80.0, 90.0, 100.0, 110.0] {
            let (r, sun) = geometry(alt, zenith);
            let exact = dense(&r, &sun, None);
            let ours = v64(&irradiance(&v32(&r), &v32(&sun), 1.0, None).unwrap());
            let err = (ours - exact).norm();
            // relative to the largest albedo a 0.30 Earth gives at this height (the subsolar
            // cap): what moves the apparent Sun
            let scale = dense(&geometry(alt, 0.0).0, &geometry(alt, 0.0).1, None).norm();
            worst_rel = worst_rel.max(err / scale);
            // the apparent Sun of a sensor facing the Sun, albedo 0.30 (the flight model's)
            let a = 0.30;
            let exact_dir = (sun + exact * a).normalize();
            let ours_dir = v64(&apparent_sun(&v32(&sun), 1.0, &v32(&(ours * a))).unwrap());
            worst_dir_deg = worst_dir_deg.max(exact_dir.angle(&ours_dir).to_degrees());
            // a sensor looking 45° off nadir: the part of the cap in its 70° field of view
            let nadir = -r.normalize();
            let boresight = (nadir + sun.cross(&nadir).normalize()).normalize();
            let cos_fov = 70f64.to_radians().cos();
            let exact_fov = dense(&r, &sun, Some((&boresight, cos_fov)));
            let fov = FieldOfView {
                boresight: v32(&boresight),
                cos_half_angle: cos_fov as f32,
            };
            let ours_fov = v64(&irradiance(&v32(&r), &v32(&sun), 1.0, Some(&fov)).unwrap());
            worst_fov_deg = worst_fov_deg.max(((ours_fov - exact_fov) * a).norm().to_degrees());
        }
    }
    println!("FIGURE albedo.quadrature.whole_cap_relative = {worst_rel:.4}");
    println!("FIGURE albedo.quadrature.apparent_sun_deg = {worst_dir_deg:.4}");
    println!("FIGURE albedo.quadrature.field_of_view_deg = {worst_fov_deg:.4}");
    // measured 0.27 %, 0.031° and 0.41° (32 points resolve a field of view's edge coarsely)
    assert!(worst_rel < 0.01, "{worst_rel}");
    assert!(worst_dir_deg < 0.05, "{worst_dir_deg}");
    assert!(worst_fov_deg < 0.5, "{worst_fov_deg}");
}

#[test]
fn night_side_inside_the_earth_and_nan() {
    let (r, sun) = geometry(500.0, 150.0);
    // the Sun below the horizon of every point of the cap: no albedo
    let d = irradiance(&v32(&r), &v32(&sun), 0.3, None).unwrap();
    assert_eq!(d, Vec3::zeros());
    assert!(irradiance(&Vec3::new(1000.0, 0.0, 0.0), &Vec3::x(), 0.3, None).is_none());
    assert!(irradiance(&Vec3::new(f32::NAN, 0.0, 7000.0), &Vec3::x(), 0.3, None).is_none());
    assert!(irradiance(&Vec3::new(0.0, 0.0, 7000.0), &Vec3::x(), f32::NAN, None).is_none());
    assert!(apparent_sun(&Vec3::zeros(), 0.0, &Vec3::zeros()).is_none());
}

/// The lit sensors' albedo: none lit, none; one lit, its own field of view's.
#[test]
fn seen_by_lit_sensors_averages_the_lit_ones() {
    use acs::attitude::Quaternion;
    let tiles = acs::tiles::cube_thesis();
    let (r, sun) = geometry(500.0, 40.0);
    let (r, sun) = (v32(&r), v32(&sun));
    let q = Quaternion::IDENTITY;
    let cos_fov = 70f32.to_radians().cos();
    let d = seen_by_lit_sensors(&tiles, &r, &sun, &q, cos_fov).unwrap();
    // by hand: the tiles whose normal is within 70° of the Sun (body = reference here)
    let lit: Vec<_> = tiles
        .iter()
        .filter(|t| t.has_working_sun_sensor() && t.normal_body().dot(&sun) >= cos_fov)
        .collect();
    assert!(!lit.is_empty());
    let mut sum = Vec3::zeros();
    for t in &lit {
        let fov = FieldOfView {
            boresight: t.normal_body(),
            cos_half_angle: cos_fov,
        };
        sum += irradiance(&r, &sun, 1.0, Some(&fov)).unwrap();
    }
    assert!((d - sum / lit.len() as f32).norm() < 1e-6, "{d:?}");
    // the Sun inside the Earth's direction of no sensor: looking away from every tile
    let none = seen_by_lit_sensors(&tiles[..0], &r, &sun, &q, cos_fov);
    assert!(none.is_none());
}
