//! Eclipse models: hand-built geometry, an independent f64 integration over the solar disc,
//! seed 003's printed shadow verdicts, and degenerate input.
//!
//! `cargo test --test eclipse -- --nocapture` prints the conical model's error statistics.

use acs::env::eclipse::{
    conical, cylindrical, EclipseError, Shadow, EARTH_RADIUS_KM, SUN_RADIUS_KM,
};
use acs::env::sun::{Sun, AU_KM};
use acs::linalg::Vec3;

fn sun_x() -> Sun {
    Sun {
        direction: Vec3::new(1.0, 0.0, 0.0),
        distance_au: 1.0,
    }
}

/// A spacecraft at radius `r_km` in the x–y plane, `angle` radians from the anti-Sun direction
/// (−x) towards +y.
fn behind(r_km: f64, angle: f64) -> Vec3 {
    Vec3::new(
        (-r_km * angle.cos()) as f32,
        (r_km * angle.sin()) as f32,
        0.0,
    )
}

/// The visible fraction of the solar disc by brute force in f64: a grid of rays over the Sun's
/// disc (tangent plane), each tested against the Earth sphere. Independent of the closed form.
fn visible_fraction_f64(r: [f64; 3], sun_km: [f64; 3]) -> f64 {
    let re = f64::from(EARTH_RADIUS_KM);
    let rs = f64::from(SUN_RADIUS_KM);
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let unit = |a: [f64; 3]| {
        let n = dot(a, a).sqrt();
        [a[0] / n, a[1] / n, a[2] / n]
    };
    let to_sun = sub(sun_km, r);
    let dist = dot(to_sun, to_sun).sqrt();
    let u = unit(to_sun);
    let helper = if u[2].abs() < 0.9 {
        [0.0, 0.0, 1.0]
    } else {
        [1.0, 0.0, 0.0]
    };
    let e1 = unit(cross(u, helper));
    let e2 = cross(u, e1);
    let a = (rs / dist).asin().tan();
    let n = 600;
    let (mut seen, mut total) = (0u64, 0u64);
    for i in 0..n {
        for j in 0..n {
            let px = (2.0 * (f64::from(i) + 0.5) / f64::from(n) - 1.0) * a;
            let py = (2.0 * (f64::from(j) + 0.5) / f64::from(n) - 1.0) * a;
            if px * px + py * py > a * a {
                continue;
            }
            total += 1;
            let d = unit([
                u[0] + px * e1[0] + py * e2[0],
                u[1] + px * e1[1] + py * e2[1],
                u[2] + px * e1[2] + py * e2[2],
            ]);
            // Ray r + t·d, t > 0, hits the sphere |x| = R⊕ if the closest approach is inside it.
            let t_closest = -dot(r, d);
            let miss2 = dot(r, r) - t_closest * t_closest;
            let blocked = t_closest > 0.0 && miss2 < re * re;
            if !blocked {
                seen += 1;
            }
        }
    }
    seen as f64 / total as f64
}

#[test]
fn full_sun_and_deep_umbra() {
    let sun = sun_x();
    // Between the Earth and the Sun: full sun.
    let r = Vec3::new(7000.0, 0.0, 0.0);
    assert!(!cylindrical(&r, &sun.direction).unwrap());
    let ill = conical(&r, &sun).unwrap();
    assert_eq!((ill.fraction, ill.shadow), (1.0, Shadow::Sunlit));
    // Over the terminator (90° from the Sun): sunlit in both.
    let r = Vec3::new(0.0, 7000.0, 0.0);
    assert!(!cylindrical(&r, &sun.direction).unwrap());
    assert_eq!(conical(&r, &sun).unwrap().shadow, Shadow::Sunlit);
    // Straight behind the Earth: deep umbra.
    for radius in [6378.2_f32, 6800.0, 7000.0, 42_164.0, 384_400.0] {
        let r = Vec3::new(-radius, 0.0, 0.0);
        assert!(cylindrical(&r, &sun.direction).unwrap(), "{radius}");
        let ill = conical(&r, &sun).unwrap();
        assert_eq!((ill.fraction, ill.shadow), (0.0, Shadow::Umbra), "{radius}");
    }
    // Far above the pole on the night side: out of the cylinder, sunlit.
    let r = Vec3::new(-7000.0, 0.0, 7000.0);
    assert!(!cylindrical(&r, &sun.direction).unwrap());
    assert_eq!(conical(&r, &sun).unwrap().fraction, 1.0);
}

/// Across the penumbra at LEO and GEO radius, against the f64 ray integration.
#[test]
fn penumbra_against_ray_integration() {
    let sun = sun_x();
    let sun_km = [f64::from(AU_KM), 0.0, 0.0];
    let mut max_err: f64 = 0.0;
    let mut sum_sq = 0.0;
    let mut count = 0;
    for radius in [6778.0_f64, 7000.0, 8000.0, 26_560.0, 42_164.0] {
        // The shadow edge is where the Earth's limb crosses the Sun's centre: sin(angle) = R/r
        // behind the Earth, to first order; sweep ±0.5° around it.
        let edge = (f64::from(EARTH_RADIUS_KM) / radius).asin();
        let mut saw_partial = false;
        for k in -50..=50 {
            let angle = edge + f64::from(k) * 0.01_f64.to_radians();
            let r = behind(radius, angle);
            let ill = conical(&r, &sun).unwrap();
            assert!((0.0..=1.0).contains(&ill.fraction));
            let r64 = [f64::from(r.x), f64::from(r.y), f64::from(r.z)];
            let reference = visible_fraction_f64(r64, sun_km);
            let err = (f64::from(ill.fraction) - reference).abs();
            if ill.shadow == Shadow::Penumbra {
                saw_partial = true;
            }
            max_err = max_err.max(err);
            sum_sq += err * err;
            count += 1;
            assert!(
                err < 3e-3,
                "r {radius} km, angle {angle} rad: conical {} vs rays {reference}",
                ill.fraction
            );
        }
        assert!(saw_partial, "no penumbra found at {radius} km");
    }
    println!(
        "conical vs f64 ray integration ({count} points across the penumbra, LEO to GEO): max {max_err:.2e}, RMS {:.2e}",
        (sum_sq / f64::from(count)).sqrt()
    );
}

/// Past the umbra's tip the Earth is a small disc inside the Sun's.
#[test]
fn antumbra() {
    let sun = sun_x();
    let r = Vec3::new(-2.0e6, 0.0, 0.0);
    let ill = conical(&r, &sun).unwrap();
    assert_eq!(ill.shadow, Shadow::Antumbra);
    let reference = visible_fraction_f64([-2.0e6, 0.0, 0.0], [f64::from(AU_KM), 0.0, 0.0]);
    assert!(
        (f64::from(ill.fraction) - reference).abs() < 3e-3,
        "{} vs {reference}",
        ill.fraction
    );
}

/// Away from the shadow edges the two models agree: cylinder ⇔ conical fraction < ½.
#[test]
fn models_agree_away_from_edges() {
    let sun = Sun {
        direction: Vec3::new(0.3, -0.8, 0.52).normalize(),
        distance_au: 0.99,
    };
    let s = sun.direction;
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut checked, mut shadowed) = (0, 0);
    for _ in 0..20_000 {
        let radius = 6600.0 + 1500.0 * next();
        let z = 2.0 * next() - 1.0;
        let phi = std::f64::consts::TAU * next();
        let rho = (1.0 - z * z).sqrt();
        let r = Vec3::new(
            (radius * rho * phi.cos()) as f32,
            (radius * rho * phi.sin()) as f32,
            (radius * z) as f32,
        );
        let off_axis = r.cross(&s).norm();
        // The penumbra and the umbra cone's taper are within ~40 km of the cylinder in LEO.
        if r.dot(&s) < 0.0 && (off_axis - EARTH_RADIUS_KM).abs() < 100.0 {
            continue;
        }
        let cyl = cylindrical(&r, &s).unwrap();
        let con = conical(&r, &sun).unwrap();
        assert_eq!(cyl, con.fraction < 0.5, "{r:?}: {con:?}");
        assert!(con.fraction == 0.0 || con.fraction == 1.0, "{r:?}: {con:?}");
        checked += 1;
        shadowed += usize::from(cyl);
    }
    assert!(checked > 15_000 && shadowed > 1_000, "{checked} {shadowed}");
}

/// Seed 003 Fig. 4.4: the document's cylindrical verdicts for its own (buggy) Sun vector.
#[test]
fn seed003_fig44_verdicts() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/seed003_fig44.csv"
    ))
    .unwrap();
    let mut rows = 0;
    for line in text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with('t'))
    {
        let f: Vec<&str> = line.split(',').collect();
        let v = |i: usize| f[i].parse::<f32>().unwrap();
        let r = Vec3::new(v(1), v(2), v(3));
        let s = Vec3::new(v(4), v(5), v(6));
        let shadow = cylindrical(&r, &s).unwrap();
        assert_eq!(shadow, f[7] == "ombra", "t = {}", f[0]);
        rows += 1;
    }
    assert_eq!(rows, 20);
}

#[test]
fn degenerate_input_is_an_error() {
    let sun = sun_x();
    let r = Vec3::new(7000.0, 0.0, 0.0);
    let nan = f32::NAN;
    let inf = f32::INFINITY;
    for bad in [
        Vec3::new(nan, 0.0, 0.0),
        Vec3::new(0.0, inf, 0.0),
        Vec3::new(0.0, 0.0, -inf),
    ] {
        assert_eq!(
            cylindrical(&bad, &sun.direction),
            Err(EclipseError::NonFinitePosition)
        );
        assert_eq!(conical(&bad, &sun), Err(EclipseError::NonFinitePosition));
        assert_eq!(cylindrical(&r, &bad), Err(EclipseError::NonFiniteSun));
        let s = Sun {
            direction: bad,
            distance_au: 1.0,
        };
        assert_eq!(conical(&r, &s), Err(EclipseError::NonFiniteSun));
    }
    // Zero vectors.
    assert_eq!(
        cylindrical(&r, &Vec3::zeros()),
        Err(EclipseError::ZeroSun(0.0))
    );
    let s = Sun {
        direction: Vec3::zeros(),
        distance_au: 1.0,
    };
    assert_eq!(conical(&r, &s), Err(EclipseError::ZeroSun(0.0)));
    assert_eq!(
        cylindrical(&Vec3::zeros(), &sun.direction),
        Err(EclipseError::InsideEarth(0.0))
    );
    assert_eq!(
        conical(&Vec3::zeros(), &sun),
        Err(EclipseError::InsideEarth(0.0))
    );
    // Inside the Earth.
    let deep = Vec3::new(0.0, 0.0, -6000.0);
    assert_eq!(conical(&deep, &sun), Err(EclipseError::InsideEarth(6000.0)));
    // Bad distances.
    for d in [0.0, -1.0, nan, inf] {
        let s = Sun {
            direction: sun.direction,
            distance_au: d,
        };
        assert!(conical(&r, &s).is_err(), "{d}");
    }
    // Overflowing magnitudes: finite components whose norm overflows.
    let huge = Vec3::new(3e38, 3e38, 3e38);
    assert!(!cylindrical(&r, &huge).unwrap());
    assert_eq!(
        cylindrical(&huge, &sun.direction),
        Err(EclipseError::TooFar(f32::INFINITY))
    );
    assert_eq!(
        conical(&huge, &sun),
        Err(EclipseError::TooFar(f32::INFINITY))
    );
    let tiny = Vec3::new(-1e-40, 0.0, 0.0);
    assert!(cylindrical(&r, &tiny).unwrap());
}
