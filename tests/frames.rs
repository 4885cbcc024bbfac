//! Tests of `acs::frames`: TEME↔ECEF, geodetic WGS-84, NED, geocentric spherical (seed 000
//! eq. 7.26), RSW, and TEME→J2000 against the STK reference pair in `tests/data/sgp4/`.
//!
//! Run with `cargo test --test frames -- --nocapture` to print the measured errors.

mod common;
mod figures;
use figures::figure;

use acs::frames::nutation::nutation;
use acs::frames::{
    cartesian_to_spherical, cartesian_to_spherical_components, ecef_to_geodetic, ecef_to_ned,
    ecef_to_ned_matrix, ecef_to_teme, ecef_to_teme_position, geodetic_to_ecef,
    inertial_to_rsw_matrix, ned_to_ecef, spherical_to_cartesian, spherical_to_cartesian_components,
    teme_to_ecef, teme_to_ecef_position, FrameError, Geodetic, Spherical, EARTH_ROTATION_RADPS,
};
use acs::frames::{j2000_to_teme, teme_to_j2000};
use acs::linalg::{Vec3, Vec3d};
use acs::time::{gmst_rad_f64, Calendar, Epoch, TimeSpan, Utc};
use core::f64::consts::{FRAC_PI_2, PI};
use nalgebra::Matrix3;

/// Deterministic pseudo-random numbers (64-bit LCG, Knuth's MMIX constants).
struct Lcg(u64);
impl Lcg {
    fn uniform(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }
}

fn orthonormality_error(m: &Matrix3<f64>) -> f64 {
    (m * m.transpose() - Matrix3::identity()).abs().max() + (m.determinant() - 1.0).abs()
}

// ---------------------------------------------------------------------------------------------
// TEME ↔ ECEF
// ---------------------------------------------------------------------------------------------

/// Vallado 2013 Example 3-15 (also his `teme2ecef` test case): 2004-04-06 07:51:28.386009 UTC,
/// UT1 − UTC = −0.439 961 9 s; TEME → PEF (no polar motion).
#[test]
fn teme_to_pef_vallado_example_3_15() {
    let utc: Epoch<Utc> = Epoch::from_calendar(Calendar {
        year: 2004,
        month: 4,
        day: 6,
        hour: 7,
        minute: 51,
        second: 28,
        nano: 386_009_000,
    })
    .unwrap();
    let ut1 = utc
        .to_ut1(Some(TimeSpan::from_seconds_f64(-0.439_961_9).unwrap()))
        .unwrap();
    let gmst = gmst_rad_f64(&ut1);
    let r_teme = Vec3d::new(5094.18016210, 6127.64465950, 6380.34453270);
    let v_teme = Vec3d::new(-4.746_131_487, 0.785_818_041, 5.531_931_288);
    let (r_pef, v_pef) = teme_to_ecef(&r_teme, &v_teme, gmst);
    let r_expected = Vec3d::new(-1033.4750313, 7901.3055856, 6380.3445327);
    let v_expected = Vec3d::new(-3.225_636_520, -2.872_451_450, 5.531_924_446);
    let dr = (r_pef - r_expected).norm();
    let dv = (v_pef - v_expected).norm();
    figure("frames.teme_pef_mm", dr * 1e6);
    println!(
        "Vallado ex. 3-15 TEME->PEF: |dr| = {:.3} mm, |dv| = {:.3} mm/s",
        dr * 1e6,
        dv * 1e6
    );
    // Vallado's `gstime` takes one f64 Julian date (resolution 4.7e-10 day): its GMST is good to
    // ±1.5e-9 rad, ±1.5 cm at |r| = 10 200 km. We measure 8.6 mm.
    assert!(dr < 1.5e-5, "{dr} km");
    // The example's velocity is ITRF: polar motion (x_p = −0.140682″, y_p = 0.333309″) turns
    // |v| = 7.5 km/s by up to 1.3 cm/s.
    assert!(dv < 1.3e-5, "{dv} km/s");
    let (r_back, v_back) = ecef_to_teme(&r_pef, &v_pef, gmst);
    assert!((r_back - r_teme).norm() < 1e-9);
    assert!((v_back - v_teme).norm() < 1e-12);
}

/// A point fixed on the Earth moves in TEME with the velocity `ecef_to_teme` gives (finite
/// differences of the position over ±0.5 s), and the f32 conversions agree with f64.
#[test]
fn teme_ecef_velocity_and_f32() {
    let r_ecef = Vec3d::new(4000.0, -3000.0, 4500.0);
    let mut rng = Lcg(3);
    let mut max_v = 0f64;
    let mut max_r32 = 0f64;
    for _ in 0..1000 {
        let theta = rng.range(0.0, 2.0 * PI);
        let dt = 0.5;
        let (_, v_teme) = ecef_to_teme(&r_ecef, &Vec3d::zeros(), theta);
        let plus = ecef_to_teme_position(&r_ecef, theta + EARTH_ROTATION_RADPS * dt);
        let minus = ecef_to_teme_position(&r_ecef, theta - EARTH_ROTATION_RADPS * dt);
        let v_fd = (plus - minus) / (2.0 * dt);
        max_v = max_v.max((v_fd - v_teme).norm());
        // f32 against f64, position in m.
        let r_teme = ecef_to_teme_position(&r_ecef, theta);
        let r32 = teme_to_ecef_position(&r_teme.cast::<f32>(), theta as f32);
        max_r32 = max_r32.max((r32.cast::<f64>() - r_ecef).norm() * 1e3);
    }
    println!("TEME<->ECEF: velocity vs finite difference {max_v:.2e} km/s; f32 position error max {max_r32:.3} m");
    assert!(max_v < 1e-9);
    assert!(max_r32 < 3.0);
}

// ---------------------------------------------------------------------------------------------
// Geodetic
// ---------------------------------------------------------------------------------------------

/// Vallado 2013 Example 3-3: r_ECEF = (6524.834, 6862.875, 6448.296) km →
/// φ_gd = 34.352 496°, λ = 46.4464°, h_ellp = 5085.22 km.
#[test]
fn geodetic_vallado_example_3_3() {
    let r = Vec3d::new(6524.834, 6862.875, 6448.296);
    let g = ecef_to_geodetic(&r).unwrap();
    // Vallado's algorithm 12 iterates to a tolerance: our latitude (exact to 1e-12 rad, see the
    // round-trip test) is 34.352 495 15°, one unit below his last printed digit (17 cm).
    assert!((g.lat_rad.to_degrees() - 34.352_496).abs() < 1e-6);
    assert!((g.lon_rad.to_degrees() - 46.446_4).abs() < 5e-5);
    assert!((g.alt_km - 5085.22).abs() < 5e-3);
    let g32 = ecef_to_geodetic(&r.cast::<f32>()).unwrap();
    assert!((f64::from(g32.lat_rad).to_degrees() - 34.352_496).abs() < 1e-5);
    assert!((f64::from(g32.alt_km) - 5085.22).abs() < 5e-3);
}

/// Round trips over heights −10…40 000 km and all latitudes, poles and equator included:
/// f64 inverse against the forward closed form; f32 inverse of the f32-rounded position,
/// measured as position error (m) of the recovered coordinates.
#[test]
fn geodetic_round_trip_accuracy() {
    let mut rng = Lcg(11);
    let (mut max64, mut max32, mut sum32, mut max_fwd32) = (0f64, 0f64, 0f64, 0f64);
    let (mut max_lat32, mut max_alt32, mut max_rel32, mut n_leo) = (0f64, 0f64, 0f64, 0u32);
    let n = 100_000;
    for i in 0..n {
        let lat = match i % 10 {
            0 => FRAC_PI_2,
            1 => -FRAC_PI_2,
            2 => 0.0,
            3 => rng.range(FRAC_PI_2 - 1e-6, FRAC_PI_2),
            _ => rng.range(-FRAC_PI_2, FRAC_PI_2),
        };
        let alt = if i % 7 == 0 {
            rng.range(-10.0, 2000.0)
        } else {
            rng.range(-10.0, 40_000.0)
        };
        let g = Geodetic {
            lat_rad: lat,
            lon_rad: rng.range(-PI, PI),
            alt_km: alt,
        };
        let r = geodetic_to_ecef(&g);
        let back = ecef_to_geodetic(&r).unwrap();
        let r_back = geodetic_to_ecef(&back);
        max64 = max64.max((r_back - r).norm() * 1e3);
        let n_plus_h = r.norm();
        max64 = max64.max((back.lat_rad - g.lat_rad).abs() * n_plus_h * 1e3);
        max64 = max64.max((back.alt_km - g.alt_km).abs() * 1e3);
        // f32
        let g32 = ecef_to_geodetic(&r.cast::<f32>()).unwrap();
        let g32d = Geodetic {
            lat_rad: f64::from(g32.lat_rad),
            lon_rad: f64::from(g32.lon_rad),
            alt_km: f64::from(g32.alt_km),
        };
        let err32 = (geodetic_to_ecef(&g32d) - r).norm() * 1e3;
        // f32 resolution grows with |r| (0.5 m at 7000 km, 4 m at 42 000 km): report LEO
        // heights (≤ 2000 km) in metres and all heights relative to |r|.
        if g.alt_km <= 2000.0 {
            max32 = max32.max(err32);
            sum32 += err32 * err32;
            n_leo += 1;
        }
        max_rel32 = max_rel32.max(err32 / (r.norm() * 1e3));
        max_lat32 = max_lat32.max((g32d.lat_rad - g.lat_rad).abs());
        max_alt32 = max_alt32.max((g32d.alt_km - g.alt_km).abs() * 1e3);
        // f32 forward
        let g_in32 = Geodetic {
            lat_rad: g.lat_rad as f32,
            lon_rad: g.lon_rad as f32,
            alt_km: g.alt_km as f32,
        };
        let r32 = geodetic_to_ecef(&g_in32).cast::<f64>();
        let r_ref = geodetic_to_ecef(&Geodetic {
            lat_rad: f64::from(g_in32.lat_rad),
            lon_rad: f64::from(g_in32.lon_rad),
            alt_km: f64::from(g_in32.alt_km),
        });
        max_fwd32 = max_fwd32.max((r32 - r_ref).norm() / r_ref.norm());
    }
    let rms32 = (sum32 / f64::from(n_leo)).sqrt();
    figure("frames.geodetic.f64_max_m", max64);
    figure("frames.geodetic.f32_leo_max_m", max32);
    figure("frames.geodetic.f32_leo_rms_m", rms32);
    figure("frames.geodetic.f32_max_rel", max_rel32);
    println!("geodetic: f64 round trip max {max64:.2e} m");
    println!("geodetic f32 inverse, heights -10..2000 km: max {max32:.3} m, RMS {rms32:.3} m (position of the result)");
    println!("geodetic f32 inverse, heights -10..40000 km: max {max_rel32:.2e} x |r|, latitude {max_lat32:.2e} rad, height {max_alt32:.3} m; forward max {max_fwd32:.2e} x |r|");
    assert!(max64 < 1e-6);
    assert!(max32 < 2.0, "{max32}");
    assert!(max_rel32 < 3e-7, "{max_rel32}"); // 5 f32 ulp of |r|
    assert!(max_fwd32 < 3e-7, "{max_fwd32}");
}

#[test]
fn geodetic_poles_and_errors() {
    let north = ecef_to_geodetic(&Vec3::new(0.0, 0.0, 6_356.752_3)).unwrap();
    assert_eq!(north.lat_rad, core::f32::consts::FRAC_PI_2);
    assert_eq!(north.lon_rad, 0.0);
    assert!(north.alt_km.abs() < 1e-3);
    let south = ecef_to_geodetic(&Vec3d::new(0.0, 0.0, -7000.0)).unwrap();
    assert_eq!(south.lat_rad, -FRAC_PI_2);
    assert!((south.alt_km - (7000.0 - 6_356.752_314_245)).abs() < 1e-9);
    let equator = ecef_to_geodetic(&Vec3d::new(0.0, -7000.0, 0.0)).unwrap();
    assert_eq!(equator.lat_rad, 0.0);
    assert!((equator.lon_rad + FRAC_PI_2).abs() < 1e-15);
    assert!((equator.alt_km - 621.863).abs() < 1e-9);
    assert_eq!(
        ecef_to_geodetic(&Vec3::new(f32::NAN, 0.0, 0.0)),
        Err(FrameError::NonFinite)
    );
    assert_eq!(
        ecef_to_geodetic(&Vec3::new(0.0, 0.0, 0.0)),
        Err(FrameError::NearCentre(0.0))
    );
}

// ---------------------------------------------------------------------------------------------
// NED and spherical
// ---------------------------------------------------------------------------------------------

#[test]
fn ned_basis() {
    let mut rng = Lcg(5);
    for _ in 0..1000 {
        let lat = rng.range(-FRAC_PI_2, FRAC_PI_2);
        let lon = rng.range(-PI, PI);
        let m = ecef_to_ned_matrix(lat, lon);
        assert!(orthonormality_error(&m) < 1e-14);
        // Down is the inward ellipsoid normal: moving along −D raises the height only.
        let g = Geodetic {
            lat_rad: lat,
            lon_rad: lon,
            alt_km: 400.0,
        };
        let up = ned_to_ecef(&Vec3d::new(0.0, 0.0, -1.0), lat, lon);
        let g2 = ecef_to_geodetic(&(geodetic_to_ecef(&g) + up)).unwrap();
        assert!((g2.alt_km - 401.0).abs() < 1e-9);
        assert!((g2.lat_rad - lat).abs() < 1e-12);
        // North points to increasing latitude, East to increasing longitude.
        let north = ned_to_ecef(&Vec3d::new(1.0, 0.0, 0.0), lat, lon);
        let g3 = ecef_to_geodetic(&(geodetic_to_ecef(&g) + north * 1e-3)).unwrap();
        assert!(g3.lat_rad > lat || lat > FRAC_PI_2 - 1e-6);
        let v = Vec3d::new(1.0, -2.0, 3.0);
        assert!((ned_to_ecef(&ecef_to_ned(&v, lat, lon), lat, lon) - v).norm() < 1e-14);
    }
    // At the north pole, North is along −x at λ = 0 and Down is −z.
    let m = ecef_to_ned_matrix(core::f32::consts::FRAC_PI_2, 0.0);
    assert!((m.row(0).transpose() - Vec3::new(-1.0, 0.0, 0.0)).norm() < 1e-7);
    assert!((m.row(2).transpose() - Vec3::new(0.0, 0.0, -1.0)).norm() < 1e-7);
}

/// Seed 000 eq. 7.26 verbatim (note 000 §2), with Dec = 90° − colatitude and RA = longitude.
fn eq_7_26(phi_r: f64, phi_colat: f64, phi_lon: f64, dec: f64, ra: f64) -> Vec3d {
    Vec3d::new(
        (phi_r * dec.cos() + phi_colat * dec.sin()) * ra.cos() - phi_lon * ra.sin(),
        (phi_r * dec.cos() + phi_colat * dec.sin()) * ra.sin() + phi_lon * ra.cos(),
        phi_r * dec.sin() - phi_colat * dec.cos(),
    )
}

#[test]
fn spherical_components_match_eq_7_26() {
    let mut rng = Lcg(9);
    let mut max32 = 0f64;
    for i in 0..10_000 {
        let colat = match i {
            0 => 0.0,
            1 => PI,
            _ => rng.range(0.0, PI),
        };
        let lon = rng.range(-PI, PI);
        let b_rtp = Vec3d::new(
            rng.range(-5e4, 5e4),
            rng.range(-5e4, 5e4),
            rng.range(-5e4, 5e4),
        );
        let expected = eq_7_26(b_rtp.x, b_rtp.y, b_rtp.z, FRAC_PI_2 - colat, lon);
        let got = spherical_to_cartesian_components(&b_rtp, colat, lon);
        assert!((got - expected).norm() < 1e-9 * b_rtp.norm());
        let back = cartesian_to_spherical_components(&got, colat, lon);
        assert!((back - b_rtp).norm() < 1e-9 * b_rtp.norm());
        let got32 =
            spherical_to_cartesian_components(&b_rtp.cast::<f32>(), colat as f32, lon as f32);
        max32 = max32.max((got32.cast::<f64>() - expected).norm() / b_rtp.norm());
        // Position round trip.
        let s = Spherical {
            r_km: 7000.0,
            colat_rad: colat,
            lon_rad: lon,
        };
        let s2 = cartesian_to_spherical(&spherical_to_cartesian(&s)).unwrap();
        assert!((s2.r_km - 7000.0).abs() < 1e-9);
        assert!((s2.colat_rad - colat).abs() < 1e-12);
        if colat > 1e-9 && colat < PI - 1e-9 {
            assert!((s2.lon_rad - lon).abs() < 1e-9);
        }
    }
    println!("spherical components f32: max relative error {max32:.2e}");
    assert!(max32 < 1e-6);
    // Poles: no division, longitude 0.
    let pole = cartesian_to_spherical(&Vec3::new(0.0, 0.0, -6400.0)).unwrap();
    assert_eq!(
        (pole.r_km, pole.colat_rad, pole.lon_rad),
        (6400.0, core::f32::consts::PI, 0.0)
    );
    assert_eq!(
        cartesian_to_spherical(&Vec3::zeros()),
        Err(FrameError::Degenerate)
    );
}

// ---------------------------------------------------------------------------------------------
// RSW
// ---------------------------------------------------------------------------------------------

#[test]
fn rsw_frame() {
    let r = Vec3d::new(-7192.627275, 456.149117, 0.066031);
    let v = Vec3d::new(0.084_891, 1.121_478, 7.350_910);
    let m = inertial_to_rsw_matrix(&r, &v).unwrap();
    assert!(orthonormality_error(&m) < 1e-14);
    let r_rsw = m * r;
    assert!((r_rsw - Vec3d::new(r.norm(), 0.0, 0.0)).norm() < 1e-9);
    let v_rsw = m * v;
    assert!(v_rsw.y > 0.0 && v_rsw.z.abs() < 1e-12);
    let m32 = inertial_to_rsw_matrix(&r.cast::<f32>(), &v.cast::<f32>()).unwrap();
    assert!((m32.cast::<f64>() - m).abs().max() < 1e-6);
    assert_eq!(
        inertial_to_rsw_matrix(&r, &(r * 2.0)),
        Err(FrameError::Degenerate)
    );
    assert_eq!(
        inertial_to_rsw_matrix(&Vec3::zeros(), &Vec3::new(1.0, 0.0, 0.0)),
        Err(FrameError::Degenerate)
    );
    assert_eq!(
        inertial_to_rsw_matrix(&Vec3::new(f32::INFINITY, 0.0, 0.0), &Vec3::x()),
        Err(FrameError::NonFinite)
    );
}

// ---------------------------------------------------------------------------------------------
// Nutation and TEME → J2000
// ---------------------------------------------------------------------------------------------

/// One row of the full IAU-1980 table of `tests/data/iau1980_nutation.txt`.
struct FullTerm {
    k: [f64; 5],
    a: f64,
    b: f64,
    c: f64,
    d: f64,
}

fn full_nutation_table() -> Vec<FullTerm> {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/iau1980_nutation.txt");
    let text = std::fs::read_to_string(path).unwrap();
    let rows: Vec<FullTerm> = text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            FullTerm {
                k: [v[0], v[1], v[2], v[3], v[4]],
                a: v[5],
                b: v[6],
                c: v[7],
                d: v[8],
            }
        })
        .collect();
    assert_eq!(rows.len(), 106);
    rows
}

/// The IAU-1980 series with its first `n` terms, in f64, written independently of the library
/// from Vallado 2013 eq. 3-82 (arguments in degrees) and returning (Δψ, Δε) in arcseconds.
fn reference_nutation_arcsec(table: &[FullTerm], n: usize, t: f64) -> (f64, f64) {
    let deg = |c0: f64, c1: f64, c2: f64, c3: f64| {
        (c0 + (c1 * t + c2 * t * t + c3 * t * t * t) / 3600.0).to_radians()
    };
    let l = deg(134.962_981_39, 1_717_915_922.633, 31.310, 0.064);
    let l1 = deg(357.527_723_33, 129_596_581.224, -0.577, -0.012);
    let f = deg(93.271_910_28, 1_739_527_263.137, -13.257, 0.011);
    let d = deg(297.850_363_06, 1_602_961_601.328, -6.891, 0.019);
    let om = deg(125.044_522_22, -6_962_890.539, 7.455, 0.008);
    let (mut dpsi, mut deps) = (0.0, 0.0);
    for term in table.iter().take(n) {
        let arg = term.k[0] * l + term.k[1] * l1 + term.k[2] * f + term.k[3] * d + term.k[4] * om;
        dpsi += (term.a + term.b * t) * arg.sin();
        deps += (term.c + term.d * t) * arg.cos();
    }
    (dpsi * 1e-4, deps * 1e-4)
}

/// Meeus (1998) example 22.a, 1987-04-10 0h TD (JDE 2 446 895.5), full IAU-1980 series:
/// Δψ = −3.788″, Δε = +9.443″, ε̄ = 23°26′27.407″.
#[test]
fn nutation_meeus_example_22a() {
    let t = (2_446_895.5 - 2_451_545.0) / 36_525.0;
    let n = nutation(t);
    let arcsec = 180.0 / PI * 3600.0;
    assert!((n.dpsi_rad * arcsec + 3.788).abs() < 0.001 + 0.0005);
    assert!((n.deps_rad * arcsec - 9.443).abs() < 0.001 + 0.0005);
    let eps0 = 23.0 * 3600.0 + 26.0 * 60.0 + 27.407;
    assert!((n.mean_obliquity_rad * arcsec - eps0).abs() < 0.0005 + 1e-6);
    let n32 = nutation(t as f32);
    assert!((f64::from(n32.dpsi_rad) * arcsec + 3.788).abs() < 0.01);
    assert!((f64::from(n32.deps_rad) * arcsec - 9.443).abs() < 0.01);
}

/// The truncation error of the first n terms against all 106, 1990–2050, for the rotation
/// TEME → J2000 (nutation enters it as Δψ sin ε̄ about the equinox and Δε), and the library's
/// f64 and f32 evaluation against the same series.
#[test]
fn nutation_truncation_and_f32() {
    let table = full_nutation_table();
    let sin_eps = (23.44f64).to_radians().sin();
    let arcsec = 180.0 / PI * 3600.0;
    let ts: Vec<f64> = (0..=2000)
        .map(|i| -0.1 + 0.6 * f64::from(i) / 2000.0)
        .collect();
    let full: Vec<(f64, f64)> = ts
        .iter()
        .map(|&t| reference_nutation_arcsec(&table, 106, t))
        .collect();
    let truncation = |n: usize| {
        ts.iter()
            .zip(&full)
            .map(|(&t, &(p, e))| {
                let (p_n, e_n) = reference_nutation_arcsec(&table, n, t);
                (((p_n - p) * sin_eps).powi(2) + (e_n - e).powi(2)).sqrt()
            })
            .fold(0.0, f64::max)
    };
    for n in [5, 10, 13, 20, 25, 30, 40, 60, 106] {
        println!(
            "nutation, first {n:3} terms: max rotation error {:.4}\"",
            truncation(n)
        );
    }
    let count = acs::frames::nutation::TERM_COUNT;
    let trunc = truncation(count);
    // The library against the reference series with the same terms, and its f32 version.
    let (mut lib64, mut lib32, mut lib32_dpsi) = (0f64, 0f64, 0f64);
    for (&t, &(p_full, e_full)) in ts.iter().zip(&full) {
        let (p, e) = reference_nutation_arcsec(&table, count, t);
        let n64 = nutation(t);
        lib64 = lib64
            .max((n64.dpsi_rad * arcsec - p).abs())
            .max((n64.deps_rad * arcsec - e).abs());
        let n32 = nutation(t as f32);
        lib32_dpsi = lib32_dpsi.max((f64::from(n32.dpsi_rad) * arcsec - p_full).abs());
        lib32 = lib32.max((f64::from(n32.deps_rad) * arcsec - e_full).abs());
    }
    figure("frames.nutation.truncation_arcsec", trunc);
    figure("frames.nutation.f32_dpsi_arcsec", lib32_dpsi);
    figure("frames.nutation.f32_deps_arcsec", lib32);
    println!("nutation library ({count} terms): f64 vs same-term reference {lib64:.1e}\"; truncation {trunc:.4}\"; f32 vs full series: dpsi {lib32_dpsi:.4}\", deps {lib32:.4}\"");
    assert!(lib64 < 1e-9);
    assert!(trunc < 0.05, "{trunc}");
    assert!(lib32_dpsi < 0.5 && lib32 < 0.5);
}

/// Every row of the DTUSAT week in TEME rotated to J2000 must match the J2000 file within 20 m
/// (0.6″ at 7000 km). Epoch of each row: the TLE epoch 09166.20608466 UTC + t; precession and
/// nutation arguments in TT (UTC + 66.184 s in 2009).
#[test]
fn teme_to_j2000_dtusat_week() {
    let read =
        |name: &str| acs::host::stk::read(&common::read_data(&format!("sgp4/{name}"))).unwrap();
    let teme_file = read("dtusat_wgs72_teme.e");
    let j2000_file = read("dtusat_wgs72_j2000.e");
    let (teme, j2000) = (&teme_file.rows, &j2000_file.rows);
    assert_eq!(teme_file.scenario_epoch, j2000_file.scenario_epoch);
    assert_eq!(teme.len(), 10_081);
    assert_eq!(teme.len(), j2000.len());
    let tle_epoch = Epoch::<Utc>::from_tle_epoch(9, 166, 20_608_466).unwrap();
    println!(
        "ScenarioEpoch {:?}; TLE epoch {:?}",
        teme_file.scenario_epoch.to_calendar(),
        tle_epoch.to_calendar()
    );
    // Diagnostic only: the frame bias J2000 → GCRS (IERS Conventions 2003 eq. 8, ξ0 = −16.617
    // mas, η0 = −6.8192 mas, dα0 = −14.6 mas, first order), to see whether the reference file's
    // "J2000" is in fact the GCRS/ICRF.
    let mas = PI / 648_000.0 / 1e3;
    let (xi0, eta0, da0) = (-16.617 * mas, -6.8192 * mas, -14.6 * mas);
    let bias = Matrix3::new(1.0, da0, -xi0, -da0, 1.0, -eta0, xi0, eta0, 1.0);
    let mut max_biased = 0f64;
    let (mut max_r, mut sum_r, mut max_v, mut max_r32) = (0f64, 0f64, 0f64, 0f64);
    for (a, b) in teme.iter().zip(j2000) {
        assert_eq!(a.t_s, b.t_s);
        let utc = tle_epoch.add(TimeSpan::from_seconds_f64(a.t_s).unwrap());
        let tt = utc.to_tt().unwrap();
        let r_teme = Vec3d::from(a.r_m);
        let v_teme = Vec3d::from(a.v_mps);
        let r_ref = Vec3d::from(b.r_m);
        let v_ref = Vec3d::from(b.v_mps);
        let (r, v) = teme_to_j2000(&r_teme, &v_teme, &tt);
        let err_r = (r - r_ref).norm();
        let err_v = (v - v_ref).norm();
        max_r = max_r.max(err_r);
        sum_r += err_r * err_r;
        max_biased = max_biased.max((bias.transpose() * r - r_ref).norm());
        max_v = max_v.max(err_v);
        // f32 matrix on f32 km.
        let (r32, _) = teme_to_j2000(
            &(r_teme / 1e3).cast::<f32>(),
            &(v_teme / 1e3).cast::<f32>(),
            &tt,
        );
        max_r32 = max_r32.max((r32.cast::<f64>() * 1e3 - r_ref).norm());
        // Inverse.
        let (r_back, _) = j2000_to_teme(&r, &v, &tt);
        assert!((r_back - r_teme).norm() < 1e-6);
    }
    let rms_r = (sum_r / teme.len() as f64).sqrt();
    figure("frames.j2000.rows", teme.len());
    figure("frames.j2000.max_m", max_r);
    figure("frames.j2000.rms_m", rms_r);
    figure("frames.j2000.f32_max_m", max_r32);
    println!("TEME->J2000, DTUSAT week, {} rows: position max {max_r:.3} m, RMS {rms_r:.3} m; velocity max {max_v:.2e} m/s; f32 position max {max_r32:.3} m", teme.len());
    println!("  (diagnostic: with the J2000->GCRS frame bias applied, max {max_biased:.3} m)");
    assert!(max_r <= 20.0, "{max_r}");
    assert!(max_r32 <= 20.0, "{max_r32}");
}
