//! Property tests (`proptest`, issue #19 item 2): invariants of the attitude algebra, the slew
//! decomposition, the wheel allocation, the time and frame conversions, the least squares, the
//! Wahba solvers and the TLE format, over random inputs.
//!
//! Every tolerance is a budget of rounding errors in the precision the code computes in, stated
//! beside it: `EPS` = f32::EPSILON = 1.19e-7 (a relative rounding is at most `EPS / 2`), and
//! `EPS64` = f64::EPSILON = 2.2e-16. A property that fails is a finding, not a tolerance to
//! widen. Failing cases proptest finds are kept in `tests/properties.proptest-regressions`.

use acs::attitude::{Dcm, Euler313, Euler321, Quaternion};
use acs::control::slew::{decompose, Branch};
use acs::control::wheels::{allocate, body_vector, Wheel};
use acs::determination::{quest, triad, wahba_svd, Observation};
use acs::frames::{ecef_to_geodetic, ecef_to_teme, geodetic_to_ecef, teme_to_ecef, Geodetic};
use acs::linalg::{Mat3, Vec3};
use acs::time::{days_from_civil, jday, Calendar, Epoch, Utc};
use acs::tle::{checksum, Tle};
use nalgebra::{Matrix3, SVector, Vector3};
use proptest::prelude::*;

/// The default configuration, failures kept beside this file
/// (`tests/properties.proptest-regressions`).
fn config() -> ProptestConfig {
    ProptestConfig {
        failure_persistence: Some(Box::new(
            proptest::test_runner::FileFailurePersistence::WithSource("proptest-regressions"),
        )),
        // the well-conditioned strategies reject some draws (κ > 30, close directions)
        max_global_rejects: 1 << 20,
        max_local_rejects: 1 << 20,
        ..ProptestConfig::default()
    }
}

const EPS: f32 = f32::EPSILON;
const EPS64: f64 = f64::EPSILON;

/// A random unit quaternion: a 4-vector of norm at least 0.1 (well away from the zero vector
/// `new_normalize` refuses), normalised.
fn quaternion() -> impl Strategy<Value = Quaternion> {
    prop::array::uniform4(-1.0f32..1.0)
        .prop_filter("norm ≥ 0.1", |v| {
            v.iter().map(|x| x * x).sum::<f32>() >= 0.01
        })
        .prop_map(|[a, b, c, d]| Quaternion::new_normalize(a, b, c, d).unwrap())
}

/// A random unit 3-vector (f64 normalisation, rounded once to f32).
fn unit_vector() -> impl Strategy<Value = Vec3> {
    prop::array::uniform3(-1.0f64..1.0)
        .prop_filter("norm ≥ 0.1", |v| {
            v.iter().map(|x| x * x).sum::<f64>() >= 0.01
        })
        .prop_map(|v| {
            let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            Vec3::new((v[0] / n) as f32, (v[1] / n) as f32, (v[2] / n) as f32)
        })
}

fn max_abs_diff(a: &Mat3, b: &Mat3) -> f32 {
    (a - b).amax()
}

/// The distance between two quaternions as attitudes (`q` and `−q` are the same).
fn quaternion_distance(a: &Quaternion, b: &Quaternion) -> f32 {
    let d = |s: f32| {
        [
            a.q0 - s * b.q0,
            a.q1 - s * b.q1,
            a.q2 - s * b.q2,
            a.q3 - s * b.q3,
        ]
        .iter()
        .fold(0.0f32, |m, x| m.max(x.abs()))
    };
    d(1.0).min(d(-1.0))
}

proptest! {
    #![proptest_config(config())]

    /// `new_normalize` gives a unit quaternion: `q/|q|` rounds each component once (≤ EPS/2
    /// relative) after a norm computed with ≤ 2 EPS relative error (four squares summed, a
    /// square root): |‖q‖ − 1| ≤ 4 EPS.
    #[test]
    fn quaternions_are_unit(q in quaternion()) {
        prop_assert!((q.norm() - 1.0).abs() <= 4.0 * EPS, "{q:?}: {}", q.norm());
        // the product of two unit quaternions: 16 products summed in fours (≤ 2 EPS each
        // component), on top of both factors' 4 EPS norm defects
        let p = q.mul(&q.conjugate().mul(&q));
        prop_assert!((p.norm() - 1.0).abs() <= 16.0 * EPS, "{p:?}");
    }

    /// The matrix of a unit quaternion is a proper rotation: each entry of `A(q)` sums four
    /// products of components ≤ 1 (≤ 2 EPS absolute) and inherits the quaternion's norm defect
    /// (≤ 2·4 EPS); an entry of `AAᵀ − I` sums three products of such entries: ≤ 2·(2 + 8) EPS
    /// + 2 EPS rounding = 22 EPS, and `det A − 1` the same budget.
    #[test]
    fn rotations_are_orthonormal_with_det_one(q in quaternion()) {
        let a = q.to_dcm();
        prop_assert!(a.orthogonality_error() <= 22.0 * EPS, "{}", a.orthogonality_error());
        prop_assert!((a.determinant() - 1.0).abs() <= 22.0 * EPS, "{}", a.determinant());
        // the composition of two rotations: a 3-term dot product more per entry (+ 2·3 EPS)
        let b = a.then(&Quaternion::new_normalize(q.q2, q.q0, -q.q3, q.q1).unwrap().to_dcm());
        prop_assert!(b.orthogonality_error() <= 34.0 * EPS, "{}", b.orthogonality_error());
        prop_assert!((b.determinant() - 1.0).abs() <= 34.0 * EPS);
    }

    /// Quaternion → DCM → quaternion: the entries of `A(q)` carry ≤ 2 EPS (above, with the
    /// norm defect); Shepperd's largest pivot is ≥ 1/4, so `q_k = ½√(pivot)` and the quotients
    /// by `4 q_k ≥ 1` keep that absolute error, plus the final normalisation: ≤ 8 EPS per
    /// component (the documented measurement is 2 EPS, `Dcm::to_quaternion`).
    #[test]
    fn quaternion_dcm_round_trip(q in quaternion()) {
        let back = q.to_dcm().to_quaternion();
        prop_assert!(back.q0 >= 0.0);
        prop_assert!(quaternion_distance(&back, &q) <= 8.0 * EPS, "{q:?} → {back:?}");
    }

    /// DCM → Euler 3-2-1 / 3-1-3 → DCM, and DCM → axis-angle → DCM: the angles are rebuilt from
    /// the matrix (`Dcm::to_euler_321`: the second and third angle from the matrix with the
    /// first removed, so even at gimbal lock they rebuild it). Budget per entry: the matrix's
    /// own 2 EPS; each of three angles ≤ 4 EPS absolute (atan2 ≤ 2 ulp of an angle ≤ π, plus
    /// its inputs' 2 EPS); the rebuilt product of three elementary rotations (≤ 3·EPS): 2 +
    /// 12 + 6 = 20 EPS.
    #[test]
    fn dcm_euler_axis_angle_round_trips(q in quaternion()) {
        let a = q.to_dcm();
        let e = a.to_euler_321();
        prop_assert!(e.theta_rad.abs() <= core::f32::consts::FRAC_PI_2 * (1.0 + EPS));
        let a321 = Dcm::from_euler_321(&e);
        prop_assert!(max_abs_diff(a321.matrix(), a.matrix()) <= 20.0 * EPS, "{e:?}");
        let e = a.to_euler_313();
        let a313 = Dcm::from_euler_313(&e);
        prop_assert!(max_abs_diff(a313.matrix(), a.matrix()) <= 20.0 * EPS, "{e:?}");
        // axis-angle through the quaternion: angle 2·atan2(|q_v|, |q0|) ≤ 2 ulp of ≤ π,
        // axis normalised (≤ 2 EPS), rebuilt through sincos and A(q): the same 20 EPS
        let aa = a.to_axis_angle();
        prop_assert!((0.0..=core::f32::consts::PI).contains(&aa.angle_rad));
        prop_assert!((aa.axis.norm() - 1.0).abs() <= 4.0 * EPS);
        let back = Dcm::from_axis_angle(&aa.axis, aa.angle_rad).unwrap();
        prop_assert!(max_abs_diff(back.matrix(), a.matrix()) <= 20.0 * EPS, "{aa:?}");
        let qa = Quaternion::from_axis_angle(&aa.axis, aa.angle_rad).unwrap();
        prop_assert!(quaternion_distance(&qa, &q) <= 20.0 * EPS);
    }

    /// Euler angles → DCM → Euler angles away from gimbal lock (cos θ ≥ 0.1): each recovered
    /// angle is an atan2 of entries with ≤ 4 EPS error whose moduli are ≥ cos θ: ≤ 4 EPS / cos θ
    /// + 2 ulp(π) ≤ 44 EPS.
    #[test]
    fn euler_dcm_euler_round_trip(
        phi in -3.1f32..3.1, theta in -1.47f32..1.47, psi in -3.1f32..3.1,
    ) {
        let e = Euler321 { phi_rad: phi, theta_rad: theta, psi_rad: psi };
        let back = Dcm::from_euler_321(&e).to_euler_321();
        for (x, y) in [(phi, back.phi_rad), (theta, back.theta_rad), (psi, back.psi_rad)] {
            prop_assert!((x - y).abs() <= 44.0 * EPS, "{e:?} → {back:?}");
        }
        let e = Euler313 { phi_rad: phi, theta_rad: theta.abs() + 0.1, psi_rad: psi };
        let back = Dcm::from_euler_313(&e).to_euler_313();
        for (x, y) in [(e.phi_rad, back.phi_rad), (e.theta_rad, back.theta_rad), (psi, back.psi_rad)] {
            prop_assert!((x - y).abs() <= 44.0 * EPS, "{e:?} → {back:?}");
        }
    }

    /// The slew decomposition recomposes the commanded rotation, on both branches and at any
    /// rotation (gimbal lock included): the Shepperd quaternion (≤ 8 EPS per component, above),
    /// Φ from an atan and its half-angle quaternion (≤ 2 ulp of π), the product q ⊗ q′* (≤ 4
    /// EPS), θ/2 and Ψ/2 by atan of the larger pair (≤ 2 ulp each), then three elementary
    /// rotations multiplied (≤ 6 EPS): ≤ 8 + 3·4 + 4 + 6 ≈ 30 EPS per entry; 32 EPS.
    #[test]
    fn slew_decomposition_recomposes(q in quaternion(), shortest in any::<bool>()) {
        let m = *q.to_dcm().matrix();
        let branch = if shortest { Branch::Shortest } else { Branch::Thesis };
        let angles = decompose(&m, branch).unwrap();
        prop_assert!(max_abs_diff(&angles.to_matrix(), &m) <= 32.0 * EPS, "{angles:?}");
    }
}

/// A wheel set of 3 to 6 random unit axes spanning the body, with its condition number (the
/// ratio of the extreme singular values of the 3×N axis matrix, computed in f64), ≤ 30.
fn wheel_set() -> impl Strategy<Value = (Vec<Vec3>, f64)> {
    prop::collection::vec(unit_vector(), 3..=6).prop_filter_map("well conditioned", |axes| {
        let mut g = Matrix3::<f64>::zeros();
        for a in &axes {
            let a = a.cast::<f64>();
            g += a * a.transpose();
        }
        let s = g.symmetric_eigenvalues();
        let (min, max) = (s.min(), s.max());
        let kappa = (max / min.max(1e-300)).sqrt();
        (kappa <= 30.0).then_some((axes, kappa))
    })
}

fn wheels<const N: usize>(axes: &[Vec3], limit: f32) -> [Wheel; N] {
    core::array::from_fn(|i| Wheel {
        axis_body: axes[i],
        limit,
        working: true,
    })
}

fn check_allocation<const N: usize>(
    axes: &[Vec3],
    kappa: f64,
    l: Vec3,
    limit: f32,
) -> Result<(), TestCaseError> {
    let w: [Wheel; N] = wheels(axes, limit);
    let a = allocate(&w, &l).unwrap();
    prop_assert_eq!(a.rank, 3);
    // The pseudoinverse of the Gram matrix G = W Wᵀ (condition κ²) is the closed form of
    // `linalg::pseudoinverse`: its documented bound is 1.6·EPS·κ(G) per entry, at most 3× that
    // normwise for 3×3 (4.8κ²·EPS); G itself is rounded when formed (a perturbation of a few EPS
    // of its largest entries, amplified by κ(G): 4κ²·EPS allowed); so (W Wᵀ)⁺L within
    // 9κ²·EPS relative, and applying it to N ≤ 6 wheels and summing their products adds
    // 2N·EPS: |ΔL| ≤ (9κ² + 2N)·EPS·|L|. (A first budget of 4κ², the inverse's alone, was
    // exceeded by 15 % at κ = 26 with 3 wheels: the rounding of G was left out.)
    let tol = (9.0 * kappa * kappa + 2.0 * N as f64) as f32 * EPS * l.norm();
    let produced = body_vector(&w, &a.wheel);
    for h in a.wheel {
        // within its limit exactly: a saturated allocation scales by one ulp less than the
        // rounded limit/max, so no rounding takes a command past the limit
        prop_assert!(h.abs() <= limit, "{h} > {limit}");
    }
    if a.scale >= 1.0 {
        // not saturated: the commanded momentum, exactly up to rounding
        prop_assert!(
            (produced - l).norm() <= tol,
            "{produced:?} vs {l:?} (tol {tol})"
        );
    } else {
        // saturated: the commanded direction, scaled
        prop_assert!(a.scale > 0.0);
        prop_assert!(
            (produced - l * a.scale).norm() <= tol * a.scale + 2.0 * EPS * produced.norm(),
            "{produced:?} vs {:?}",
            l * a.scale
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(config())]

    /// Wheel allocation reproduces the commanded momentum when no wheel saturates, and keeps
    /// its direction (a uniform scale) when one does.
    #[test]
    fn wheel_allocation_reproduces_or_keeps_direction(
        (axes, kappa) in wheel_set(), l in unit_vector(), size in 1e-6f32..1e-2, limit in 1e-4f32..1e-2,
    ) {
        let l = l * size;
        match axes.len() {
            3 => check_allocation::<3>(&axes, kappa, l, limit)?,
            4 => check_allocation::<4>(&axes, kappa, l, limit)?,
            5 => check_allocation::<5>(&axes, kappa, l, limit)?,
            _ => check_allocation::<6>(&axes, kappa, l, limit)?,
        }
    }
}

/// A valid calendar instant, 1900-03-01 .. 2100-02-28 (the range `jday` covers), no leap second.
fn calendar() -> impl Strategy<Value = Calendar> {
    (
        1900i32..=2100,
        1u8..=12,
        1u8..=31,
        0u8..24,
        0u8..60,
        0u8..60,
        0u32..1_000_000_000,
    )
        .prop_filter_map(
            "a date in jday's range",
            |(year, month, day, hour, minute, second, nano)| {
                let c = Calendar {
                    year,
                    month,
                    day,
                    hour,
                    minute,
                    second,
                    nano,
                };
                let e = Epoch::<Utc>::from_calendar(c).ok()?;
                let lo = Epoch::<Utc>::from_calendar(Calendar {
                    year: 1900,
                    month: 3,
                    day: 1,
                    hour: 0,
                    minute: 0,
                    second: 0,
                    nano: 0,
                })
                .ok()?;
                let hi = Epoch::<Utc>::from_calendar(Calendar {
                    year: 2100,
                    month: 2,
                    day: 28,
                    hour: 23,
                    minute: 59,
                    second: 59,
                    nano: 999_999_999,
                })
                .ok()?;
                (e.span_since(&lo).as_seconds_f64() >= 0.0
                    && hi.span_since(&e).as_seconds_f64() >= 0.0)
                    .then_some(c)
            },
        )
}

proptest! {
    #![proptest_config(config())]

    /// Calendar → epoch → calendar is the identity; epoch → split Julian date → epoch is the
    /// identity to the nanosecond (the fraction of a day in f64 resolves 2⁻⁵³ day = 1e-11 s,
    /// far below the half nanosecond `from_jd_split` rounds to); `jday` equals `jd_split`
    /// exactly (both are sums of exact f64 integers and one division).
    #[test]
    fn calendar_epoch_julian_round_trips(c in calendar()) {
        let e = Epoch::<Utc>::from_calendar(c).unwrap();
        prop_assert_eq!(e.to_calendar(), c);
        let (w, f) = e.jd_split();
        prop_assert_eq!(Epoch::<Utc>::from_jd_split(w, f).unwrap(), e);
        let (jw, jf) = jday(&c).unwrap();
        prop_assert_eq!(jw + jf, w + f, "jday {} + {} vs jd_split {} + {}", jw, jf, w, f);
        // any other split of the same date: whole days moved between the parts
        prop_assert_eq!(Epoch::<Utc>::from_jd_split(w - 3.0, f + 3.0).unwrap(), e);
    }

    /// TEME → ECEF → TEME (f64) returns the state: two 3×3 rotations (≤ 3 roundings each, 6
    /// EPS64 relative) and the Earth-rate cross products (ω|r| ≤ 3.3 km/s at 45 000 km, a few
    /// roundings): |Δr| ≤ 8 EPS64 |r|, |Δv| ≤ 8 EPS64 (|v| + ω|r|).
    #[test]
    fn teme_ecef_round_trip(
        r in unit_vector(), rn in 6_000.0f64..45_000.0, v in unit_vector(), vn in 0.0f64..10.0,
        gmst in 0.0f64..core::f64::consts::TAU,
    ) {
        let r: Vector3<f64> = r.cast::<f64>() * rn;
        let v: Vector3<f64> = v.cast::<f64>() * vn;
        let (re, ve) = teme_to_ecef(&r, &v, gmst);
        let (rt, vt) = ecef_to_teme(&re, &ve, gmst);
        let w = 7.292_115e-5 * rn;
        prop_assert!((rt - r).norm() <= 8.0 * EPS64 * rn, "{}", (rt - r).norm());
        prop_assert!((vt - v).norm() <= 8.0 * EPS64 * (vn + w), "{}", (vt - v).norm());
    }

    /// ECEF → geodetic → ECEF (f64) and geodetic → ECEF → geodetic, heights −10 … 40 000 km
    /// (`ecef_to_geodetic`'s documented domain; measured ≤ 2.3e-8 m, 3.3 EPS64·|r| at the
    /// surface). Budget: the closed form's square roots, divisions and normalised sine/cosine
    /// pairs, some 20 roundings of quantities ≤ |r|, and the rebuilt position's (a few more):
    /// 32 EPS64 |r|; latitude to 32 EPS64 rad (a position error over |r|), longitude to
    /// 32 EPS64 / cos φ (over the distance from the polar axis).
    #[test]
    fn ecef_geodetic_round_trips(
        lat in -1.57f64..1.57, lon in -3.1f64..3.1, alt in -10.0f64..40_000.0,
    ) {
        let g = Geodetic { lat_rad: lat, lon_rad: lon, alt_km: alt };
        let r = geodetic_to_ecef(&g);
        let back = ecef_to_geodetic(&r).unwrap();
        let rn = r.norm();
        prop_assert!((geodetic_to_ecef(&back) - r).norm() <= 32.0 * EPS64 * rn);
        prop_assert!((back.lat_rad - lat).abs() <= 32.0 * EPS64, "{g:?} → {back:?}");
        // longitude is a position error over the distance from the axis, |r| cos φ
        prop_assert!((back.lon_rad - lon).abs() <= 32.0 * EPS64 / lat.cos(), "{g:?} → {back:?}");
        prop_assert!((back.alt_km - alt).abs() <= 32.0 * EPS64 * rn, "{g:?} → {back:?}");
    }
}

proptest! {
    #![proptest_config(config())]

    /// Least squares is exact on consistent data: rows `aᵢ`, right-hand sides `aᵢ·x` (computed
    /// in f64, rounded once), `x` recovered to (4κ² + 8)·EPS relative (Givens QR in f32: the
    /// solution's relative error is of order κ·EPS for consistent data, κ² bounding the
    /// normal-equation path `inverse_gram` takes; 8 for the right-hand sides' rounding).
    #[test]
    fn least_squares_exact_on_consistent_data(
        rows in prop::collection::vec(prop::array::uniform3(-1.0f32..1.0), 3..=12),
        x in prop::array::uniform3(-100.0f32..100.0),
    ) {
        let rows: Vec<Vec3> = rows.into_iter().map(Vec3::from).collect();
        let mut g = Matrix3::<f64>::zeros();
        for a in &rows {
            let a = a.cast::<f64>();
            g += a * a.transpose();
        }
        let s = g.symmetric_eigenvalues();
        let kappa = (s.max() / s.min().max(1e-300)).sqrt();
        prop_assume!(kappa <= 30.0);
        let x = Vec3::from(x);
        let mut ls = acs::linalg::lsq::QrLeastSquares::<1>::new();
        for a in &rows {
            let y = a.cast::<f64>().dot(&x.cast::<f64>()) as f32;
            ls.push(a, &SVector::<f32, 1>::new(y)).unwrap();
        }
        let tol = (4.0 * kappa * kappa + 8.0) as f32 * EPS * x.norm().max(1.0);
        let got = ls.solve_full_rank(1e-5).unwrap().column(0).into_owned();
        prop_assert!((got - x).norm() <= tol, "{got:?} vs {x:?} (κ {kappa})");
        let inv = ls.inverse_gram(1e-5).unwrap();
        prop_assert!(inv.iter().all(|v| v.is_finite()));
    }

    /// The tiles' magnetometer and gyro least squares (`determination::least_squares`) on the
    /// thesis's cube are exact on consistent readings: each tile's tile-frame components of
    /// the body vector (rotated in f64, rounded once); the cube's rows are orthonormal (κ = 1):
    /// 16 EPS relative.
    #[test]
    fn tile_least_squares_exact(b in unit_vector(), size in 1.0f32..60_000.0, missing in 0usize..7) {
        use acs::determination::least_squares::{angular_rate_body, magnetic_field_body};
        let tiles = acs::tiles::cube_thesis();
        let b = b * size;
        let readings: Vec<Option<acs::linalg::Vec2>> = tiles.iter().enumerate().map(|(i, t)| {
            (i != missing).then(|| acs::linalg::Vec2::new(
                t.x_body().cast::<f64>().dot(&b.cast::<f64>()) as f32,
                t.y_body().cast::<f64>().dot(&b.cast::<f64>()) as f32,
            ))
        }).collect();
        let got = magnetic_field_body(&tiles, &readings).unwrap();
        prop_assert!((got - b).norm() <= 16.0 * EPS * size, "{got:?} vs {b:?}");
        let rates: Vec<Option<f32>> = tiles.iter().enumerate().map(|(i, t)| {
            (i != missing).then(|| t.normal_body().cast::<f64>().dot(&b.cast::<f64>()) as f32)
        }).collect();
        // with one tile missing, an axis can be left without a gyro (not every tile has one):
        // then the refusal is the right answer
        let got = match angular_rate_body(&tiles, &rates) {
            Ok(got) => got,
            Err(acs::determination::DeterminationError::NotObservable { .. }) => {
                let all: Vec<Option<f32>> = tiles.iter().map(|t| Some(t.normal_body().cast::<f64>().dot(&b.cast::<f64>()) as f32)).collect();
                angular_rate_body(&tiles, &all).unwrap()
            }
            Err(e) => return Err(TestCaseError::fail(format!("{e}"))),
        };
        prop_assert!((got - b).norm() <= 16.0 * EPS * size, "{got:?} vs {b:?}");
    }
}

/// Observations of a rotation without noise: reference unit vectors, body = A·r (f64, rounded
/// once), random weights, every pair of directions at least 0.2 rad from parallel or
/// antiparallel.
fn observations() -> impl Strategy<Value = (Quaternion, Vec<Observation>, f32)> {
    (
        quaternion(),
        prop::collection::vec((unit_vector(), 0.1f32..10.0), 2..=6),
    )
        .prop_filter_map("separated directions", |(q, refs)| {
            let min_sin = refs
                .iter()
                .enumerate()
                .flat_map(|(i, a)| refs[i + 1..].iter().map(move |b| a.0.cross(&b.0).norm()))
                .fold(1.0f32, f32::min);
            if min_sin < 0.2 {
                return None;
            }
            let a = q.to_dcm().matrix().cast::<f64>();
            let obs = refs
                .iter()
                .map(|(r, w)| Observation {
                    body: (a * r.cast::<f64>()).cast::<f32>(),
                    reference: *r,
                    weight: *w,
                })
                .collect();
            Some((q, obs, min_sin))
        })
}

proptest! {
    #![proptest_config(config())]

    /// Every Wahba solver is exact on noise-free vectors, to the precision the data allows.
    /// The inputs are rounded to f32 (≤ EPS in direction each); an attitude error δθ raises
    /// the loss by ½ δθᵀ F δθ, F = Σ wᵢ (I − rᵢ rᵢᵀ) (the Fisher information; its smallest
    /// eigenvalue f_min is also the eigengap of Davenport's K that QUEST's eigenvector depends
    /// on), so a direction error δ on vector i moves the optimum by ≤ wᵢ δ / f_min: the data
    /// fix the attitude to EPS Σw / f_min. The solvers' own f32 work (an SVD, QUEST's quartic
    /// and eigenvector, a Gauss–Newton step, TRIAD's cross products) operates on quantities of
    /// size Σw with a handful of roundings each: 8 EPS Σw / f_min in all.
    #[test]
    fn wahba_solvers_exact_without_noise((q, obs, _min_sin) in observations()) {
        let mut f = Matrix3::<f64>::zeros();
        let mut sum_w = 0.0f64;
        for o in &obs {
            let r = o.reference.cast::<f64>();
            f += (Matrix3::identity() - r * r.transpose()) * f64::from(o.weight);
            sum_w += f64::from(o.weight);
        }
        let f_min = f.symmetric_eigenvalues().min();
        let tol = (8.0 * f64::from(EPS) * sum_w / f_min) as f32;
        let truth = q.to_dcm();
        let check = |name: &str, s: acs::determination::Solution| -> Result<(), TestCaseError> {
            let err = truth.angle_to(&s.dcm);
            prop_assert!(err <= tol, "{}: {} rad > {} (q {:?})", name, err, tol, q);
            prop_assert!(s.quaternion.to_dcm().angle_to(&truth) <= tol, "{}: quaternion", name);
            Ok(())
        };
        check("wahba_svd", wahba_svd::solve(&obs).unwrap())?;
        check("wahba_svd raw", wahba_svd::solve_raw(&obs).unwrap())?;
        check("quest", quest::solve(&obs).unwrap())?;
        check("quest raw", quest::solve_raw(&obs).unwrap())?;
        if obs.len() == 2 {
            // the flight loop's two-observation path (its F is the one above)
            check("wahba_svd pair", wahba_svd::solve_pair(&obs[0], &obs[1]).unwrap())?;
        }
        // TRIAD takes the first vector exactly and the second's direction about it: ≤ 8 EPS
        // over the sine of their angle (≥ 0.2)
        let pair_sin = obs[0].reference.cross(&obs[1].reference).norm();
        let triad_tol = 8.0 * EPS / pair_sin;
        let err = truth.angle_to(&triad::solve(&obs).unwrap().dcm);
        prop_assert!(err <= triad_tol, "triad: {} > {}", err, triad_tol);
    }
}

/// The fields of a TLE as integers in their columns' ranges.
#[derive(Debug, Clone)]
struct Fields {
    catalog: u32,
    yy: u32,
    doy: u32,
    day_frac: u32,
    ndot: i64,
    nddot: (i32, i32),
    bstar: (i32, i32),
    elset: u32,
    inc: u32,
    raan: u32,
    ecc: u32,
    argp: u32,
    ma: u32,
    n: u64,
    rev: u32,
}

fn fields() -> impl Strategy<Value = Fields> {
    (
        (
            0u32..100_000,
            0u32..100,
            1u32..=365,
            0u32..100_000_000,
            -99_999_999i64..=99_999_999,
        ),
        (
            (-99_999i32..=99_999, -9i32..=9),
            (-99_999i32..=99_999, -9i32..=9),
            0u32..10_000,
        ),
        (
            0u32..=1_800_000,
            0u32..3_600_000,
            0u32..10_000_000,
            0u32..3_600_000,
            0u32..3_600_000,
        ),
        (1u64..=9_999_999_999, 0u32..100_000),
    )
        .prop_map(
            |(
                (catalog, yy, doy, day_frac, ndot),
                (nddot, bstar, elset),
                (inc, raan, ecc, argp, ma),
                (n, rev),
            )| Fields {
                catalog,
                yy,
                doy,
                day_frac,
                ndot,
                nddot,
                bstar,
                elset,
                inc,
                raan,
                ecc,
                argp,
                ma,
                n,
                rev,
            },
        )
}

fn exp_field((m, e): (i32, i32)) -> String {
    let sign = if m < 0 { '-' } else { ' ' };
    let esign = if e < 0 { '-' } else { '+' };
    format!("{sign}{:05}{esign}{}", m.unsigned_abs(), e.unsigned_abs())
}

fn angle(x: u32) -> String {
    format!("{:3}.{:04}", x / 10_000, x % 10_000)
}

impl Fields {
    /// The two lines of the format (columns of `acs::tle`), checksums computed.
    fn lines(&self) -> (String, String) {
        let ndot_sign = if self.ndot < 0 { '-' } else { ' ' };
        let l1 = format!(
            "1 {:05}U 98067A   {:02}{:03}.{:08} {ndot_sign}.{:08} {} {} 0 {:4}",
            self.catalog,
            self.yy,
            self.doy,
            self.day_frac,
            self.ndot.unsigned_abs(),
            exp_field(self.nddot),
            exp_field(self.bstar),
            self.elset,
        );
        let l2 = format!(
            "2 {:05} {} {} {:07} {} {} {:2}.{:08}{:5}",
            self.catalog,
            angle(self.inc),
            angle(self.raan),
            self.ecc,
            angle(self.argp),
            angle(self.ma),
            self.n / 100_000_000,
            self.n % 100_000_000,
            self.rev,
        );
        let c1 = checksum(l1.as_bytes());
        let c2 = checksum(l2.as_bytes());
        (format!("{l1}{c1}"), format!("{l2}{c2}"))
    }
}

proptest! {
    #![proptest_config(config())]

    /// TLE format → parse: every field read back as written. Decimal fields to 4 EPS64
    /// relative (a decimal integer, exact in f64, divided or scaled by a power of ten: one or
    /// two roundings); the epoch exactly (1e-8 day = 864 µs, a whole number of nanoseconds).
    #[test]
    fn tle_format_parse_round_trip(f in fields()) {
        let (l1, l2) = f.lines();
        prop_assert_eq!(l1.len(), 69);
        prop_assert_eq!(l2.len(), 69);
        let year = if f.yy < 57 { 2000 + f.yy as i32 } else { 1900 + f.yy as i32 };
        let leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
        prop_assume!(f.doy <= if leap { 366 } else { 365 });
        let t = Tle::parse(&l1, &l2).map_err(|e| TestCaseError::fail(format!("{l1}\n{l2}\n{e}")))?;
        let close = |got: f64, want: f64| (got - want).abs() <= 4.0 * EPS64 * want.abs();
        prop_assert_eq!(t.catalog_number, f.catalog);
        prop_assert_eq!(t.element_set_number as u32, f.elset);
        prop_assert_eq!(t.revolution_number, f.rev);
        prop_assert_eq!(t.international_designator.as_str(), "98067A");
        let jan1 = days_from_civil(year, 1, 1);
        let nanos = u64::from(f.day_frac) * 864_000;
        let epoch = Epoch::<Utc>::from_parts(
            jan1 + f.doy as i32 - 1,
            (nanos / 1_000_000_000) as u32,
            (nanos % 1_000_000_000) as u32,
        ).unwrap();
        prop_assert_eq!(t.epoch, epoch, "{}", l1);
        prop_assert!(close(t.mean_motion_dot, f.ndot as f64 * 1e-8), "{} vs {}", t.mean_motion_dot, f.ndot);
        let expo = |(m, e): (i32, i32)| f64::from(m) * 1e-5 * 10f64.powi(e);
        prop_assert!(close(t.mean_motion_ddot, expo(f.nddot)), "{} {:?}", t.mean_motion_ddot, f.nddot);
        prop_assert!(close(t.bstar, expo(f.bstar)), "{} {:?}", t.bstar, f.bstar);
        prop_assert!(close(t.inclination_deg, f64::from(f.inc) / 1e4));
        prop_assert!(close(t.raan_deg, f64::from(f.raan) / 1e4));
        prop_assert!(close(t.eccentricity, f64::from(f.ecc) / 1e7));
        prop_assert!(close(t.arg_perigee_deg, f64::from(f.argp) / 1e4));
        prop_assert!(close(t.mean_anomaly_deg, f64::from(f.ma) / 1e4));
        prop_assert!(close(t.mean_motion_rev_per_day, f.n as f64 / 1e8), "{} vs {}", t.mean_motion_rev_per_day, f.n);
    }
}
