//! Control: principal axes, slew decomposition and planning, wheel allocation, against the
//! thesis's numbers (note 000 §4.2–4.4, §4.8; data in tests/data/thesis_control.txt).

use std::collections::HashMap;

use acs::attitude::Dcm;
use acs::control::principal_axes::{principal_axes, PrincipalAxes, PrincipalAxesError};
use acs::control::slew::{decompose, manoeuvre_matrix, plan, step_for, Branch, SlewLimits};
use acs::control::wheels::{allocate, body_vector, Allocator, Wheel, WheelError};
use acs::linalg::{Mat3, Vec3};

fn data() -> HashMap<String, Vec<f64>> {
    let text = include_str!("data/thesis_control.txt");
    text.lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .map(|l| {
            let (k, v) = l.split_once('=').expect("key = values");
            let nums = v
                .split_whitespace()
                .map(|x| x.parse::<f64>().expect("number"))
                .collect();
            (k.trim().to_string(), nums)
        })
        .collect()
}

fn mat(d: &HashMap<String, Vec<f64>>, k: &str) -> Mat3 {
    let v = &d[k];
    assert_eq!(v.len(), 9, "{k}");
    Mat3::from_row_iterator(v.iter().map(|x| *x as f32))
}

fn vec3(d: &HashMap<String, Vec<f64>>, k: &str) -> Vec3 {
    let v = &d[k];
    assert_eq!(v.len(), 3, "{k}");
    Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32)
}

/// Relative error of a vector: ‖a − b‖ / ‖b‖.
fn rel(a: &Vec3, b: &Vec3) -> f32 {
    (a - b).norm() / b.norm()
}

/// The thesis's principal axes exactly as printed (E, I'), with its inertia tensor.
fn thesis_axes(d: &HashMap<String, Vec<f64>>) -> PrincipalAxes {
    PrincipalAxes {
        e: mat(d, "e"),
        moments: vec3(d, "moments"),
        inertia_body: mat(d, "inertia"),
    }
}

#[test]
fn principal_axes_reproduce_thesis_e_and_moments() {
    let d = data();
    let axes = principal_axes(&mat(&d, "inertia")).unwrap();
    let e_err = (axes.e - mat(&d, "e")).abs().max();
    let m_err = rel(&axes.moments, &vec3(&d, "moments"));
    println!("principal axes: max |E - E_thesis| = {e_err:.3e}, moments rel err = {m_err:.3e}");
    // bound: eps_f32 * |I| / gap = 6e-8 * 7.3e-3 / 4.1e-5 ~ 1e-5 (module docs)
    assert!(e_err < 2e-5, "{e_err}");
    assert!(m_err < 1e-6, "{m_err}");
    // right-handed, positive diagonal, I' = E I Eᵀ
    assert!((axes.e.determinant() - 1.0).abs() < 1e-5);
    assert!(axes.e.m11 > 0.0 && axes.e.m22 > 0.0 && axes.e.m33 > 0.0);
    let diag = axes.e * axes.inertia_body * axes.e.transpose();
    assert!((diag - Mat3::from_diagonal(&axes.moments)).abs().max() < 1e-9);
}

#[test]
fn principal_axes_stable_under_perturbation_of_the_near_degenerate_pair() {
    // I_a and I_c differ by 0.6 %: a relative perturbation of 1e-6 of the tensor must move E by
    // no more than its conditioning allows (1e-6 * |I| / gap ~ 2e-4), and keep the ordering.
    let d = data();
    let base = principal_axes(&mat(&d, "inertia")).unwrap();
    for k in 0..9 {
        let mut i = mat(&d, "inertia");
        let (r, c) = (k / 3, k % 3);
        let delta = 1e-6 * 7.3e-3;
        i[(r, c)] += delta;
        i[(c, r)] = i[(r, c)];
        let p = principal_axes(&i).unwrap();
        let de = (p.e - base.e).abs().max();
        assert!(de < 3e-4, "perturbation {k}: {de}");
    }
}

#[test]
fn principal_axes_reject_bad_tensors() {
    let mut nan = Mat3::identity();
    nan.m12 = f32::NAN;
    assert_eq!(principal_axes(&nan), Err(PrincipalAxesError::NotFinite));
    let mut asym = Mat3::identity();
    asym.m12 = 0.1;
    assert!(matches!(
        principal_axes(&asym),
        Err(PrincipalAxesError::NotSymmetric(_))
    ));
    // violates I_a + I_b >= I_c
    let bad = Mat3::from_diagonal(&Vec3::new(1.0, 1.0, 3.0));
    assert!(matches!(
        principal_axes(&bad),
        Err(PrincipalAxesError::NotPhysical(_))
    ));
    let neg = Mat3::from_diagonal(&Vec3::new(-1.0, 1.0, 1.0));
    assert!(matches!(
        principal_axes(&neg),
        Err(PrincipalAxesError::NotPhysical(_))
    ));
    // already diagonal and a sphere: E = I
    let sphere = principal_axes(&Mat3::from_diagonal(&Vec3::new(2.0, 2.0, 2.0))).unwrap();
    assert_eq!(sphere.e, Mat3::identity());
}

#[test]
fn chapter10_example() {
    let d = data();
    let axes = thesis_axes(&d);
    let a_d = Dcm::from_matrix_unchecked(mat(&d, "a_d"));
    let m = manoeuvre_matrix(&Dcm::identity(), &a_d, &axes);
    let m_err = (m - mat(&d, "ch10_m_abc")).abs().max();
    assert!(m_err < 1e-6, "{m_err}");
    let ang = decompose(&m, Branch::Thesis).unwrap();
    let expected = &d["ch10_psi_theta_phi_deg"];
    let got = [
        ang.psi_c.to_degrees(),
        ang.theta_b.to_degrees(),
        ang.phi_a.to_degrees(),
    ];
    let mut worst = 0.0f64;
    for (g, e) in got.iter().zip(expected) {
        worst = worst.max(((*g as f64) - e).abs() / e.abs());
    }
    println!("chapter 10: worst relative angle error {worst:.2e}");
    assert!(worst < 1e-5, "{got:?} vs {expected:?}");
    assert!((ang.to_matrix() - m).abs().max() < 2e-6);

    // 5 s per rotation: rates and momenta (eqs. 10.27–10.29)
    let steps = [
        step_for(&axes, 2, ang.psi_c, 5.0),
        step_for(&axes, 1, ang.theta_b, 5.0),
        step_for(&axes, 0, ang.phi_a, 5.0),
    ];
    let omegas = ["ch10_omega_1uvw", "ch10_omega_2uvw", "ch10_omega_3uvw"];
    let momenta = ["ch10_l_1uvw", "ch10_l_2uvw", "ch10_l_3uvw"];
    let torques = ["ch10_m1", "ch10_m2", "ch10_m3"];
    for (k, s) in steps.iter().enumerate() {
        let w = rel(&s.omega_body_radps, &vec3(&d, omegas[k]));
        let l = rel(&s.h_body, &vec3(&d, momenta[k]));
        let t = rel(&(s.h_body / 1e-4), &vec3(&d, torques[k]));
        println!("chapter 10 step {k}: rel err omega {w:.2e}, L {l:.2e}, impulse torque {t:.2e}");
        assert!(w < 1e-5 && l < 1e-5 && t < 1e-5, "step {k}: {w} {l} {t}");
    }
    let omega_abc = [
        vec3(&d, "ch10_omega_c"),
        vec3(&d, "ch10_omega_b"),
        vec3(&d, "ch10_omega_a"),
    ];
    for (s, w) in steps.iter().zip(omega_abc.iter()) {
        assert!(rel(&(axes.e * s.omega_body_radps), w) < 1e-5);
    }
}

fn thesis_limits() -> SlewLimits {
    // The thesis gives no values; its tests imply t_min = 0.3 s with every default-L time
    // shorter than that (note 000 §3.10): a wheel of 1 kg·m²/s, 5 wheels (cube), l_min 1e-6.
    SlewLimits {
        l_max: 1.0,
        l_min: 1e-6,
        t_min: 0.3,
        default_fraction: 0.85,
        wheels_per_axis: [2, 2, 2],
    }
}

fn check_thesis_test(d: &HashMap<String, Vec<f64>>, a: &Dcm, prefix: &str) {
    let axes = thesis_axes(d);
    let a_d = Dcm::from_matrix_unchecked(mat(d, "a_d"));
    let m = manoeuvre_matrix(a, &a_d, &axes);
    let ang = decompose(&m, Branch::Thesis).unwrap();
    let expected = vec3(d, &format!("{prefix}_angle"));
    let got = Vec3::new(ang.phi_a, ang.theta_b, ang.psi_c);
    let angle_err = rel(&got, &expected);
    let p = plan(&axes, &ang, &thesis_limits(), 100.0).unwrap();
    let times = [
        p.steps[2].duration_s,
        p.steps[1].duration_s,
        p.steps[0].duration_s,
    ];
    for t in times {
        assert!((t - 0.3).abs() < 1e-7);
    }
    // L3 = first (about C), L2 = second (about B), L1 = third (about A)
    let l_err = [
        rel(&p.steps[0].h_body, &vec3(d, &format!("{prefix}_l3"))),
        rel(&p.steps[1].h_body, &vec3(d, &format!("{prefix}_l2"))),
        rel(&p.steps[2].h_body, &vec3(d, &format!("{prefix}_l1"))),
    ];
    println!("{prefix}: angle rel err {angle_err:.2e}, L3 L2 L1 rel err {l_err:?}");
    assert!(angle_err < 1e-5, "{got:?} vs {expected:?}");
    for e in l_err {
        assert!(e < 1e-5, "{e}");
    }
}

#[test]
fn thesis_test1_control() {
    let d = data();
    let a = Dcm::from_matrix_unchecked(mat(&d, "a_true"));
    check_thesis_test(&d, &a, "test1");
}

#[test]
fn thesis_test2_control_from_noisy_attitude() {
    // The thesis plans from its determined (non-orthogonal) attitude A_obt = A_eo · A.
    let d = data();
    let a = Dcm::from_matrix_unchecked(mat(&d, "test2_a_eo") * mat(&d, "a_true"));
    check_thesis_test(&d, &a, "test2");
}

#[test]
fn test1_shortest_branch_halves_the_rotation() {
    let d = data();
    let axes = thesis_axes(&d);
    let a = Dcm::from_matrix_unchecked(mat(&d, "a_true"));
    let m = manoeuvre_matrix(&a, &Dcm::from_matrix_unchecked(mat(&d, "a_d")), &axes);
    let thesis = decompose(&m, Branch::Thesis).unwrap();
    let short = decompose(&m, Branch::Shortest).unwrap();
    let totals = &d["test1_total_deg"];
    assert!((thesis.total_rad().to_degrees() as f64 - totals[0]).abs() < 0.05);
    assert!((short.total_rad().to_degrees() as f64 - totals[1]).abs() < 0.05);
    let e = vec3(&d, "test1_shortest_angle");
    let got = Vec3::new(short.phi_a, short.theta_b, short.psi_c);
    assert!((got - e).abs().max() < 1e-4, "{got:?}"); // printed to 4 decimals
    assert!((short.to_matrix() - m).abs().max() < 2e-6);
}

#[test]
fn decomposition_singular_cases_have_no_nan_and_reconstruct() {
    let cases = [
        Dcm::identity(),
        Dcm::a2(std::f32::consts::FRAC_PI_2),  // θ = +90°
        Dcm::a2(-std::f32::consts::FRAC_PI_2), // θ = −90°
        Dcm::a3(0.3)
            .then(&Dcm::a2(std::f32::consts::FRAC_PI_2))
            .then(&Dcm::a1(0.4)),
        Dcm::a1(std::f32::consts::PI), // 180° about A
        Dcm::a3(std::f32::consts::PI), // 180° about C: q0'''' = 0
        Dcm::a2(std::f32::consts::PI), // 180° about B
        Dcm::a3(std::f32::consts::PI).then(&Dcm::a2(std::f32::consts::PI)),
        Dcm::a1(std::f32::consts::FRAC_PI_2), // B = 0
    ];
    for (k, c) in cases.iter().enumerate() {
        for branch in [Branch::Thesis, Branch::Shortest] {
            let a = decompose(c.matrix(), branch).unwrap();
            assert!(a.phi_a.is_finite() && a.theta_b.is_finite() && a.psi_c.is_finite());
            let err = (a.to_matrix() - c.matrix()).abs().max();
            assert!(err < 5e-6, "case {k} {branch:?}: {a:?} err {err}");
        }
    }
    let mut nan = Mat3::identity();
    nan.m22 = f32::NAN;
    assert!(decompose(&nan, Branch::Thesis).is_err());
}

#[test]
fn planner_limits_and_errors() {
    let d = data();
    let axes = thesis_axes(&d);
    let ang = decompose(&Dcm::a1(0.5).matrix().clone_owned(), Branch::Thesis).unwrap();
    // too slow even at l_max
    let slow = SlewLimits {
        l_max: 1e-4,
        ..thesis_limits()
    };
    assert!(matches!(
        plan(&axes, &ang, &slow, 1.0),
        Err(acs::control::slew::SlewError::TooSlow { .. })
    ));
    // default fraction too slow, full momentum fits: uses l_max
    let l = 0.5 * axes.moments.x / 1.0; // 1 s at full momentum with one wheel
    let lim = SlewLimits {
        l_max: l,
        wheels_per_axis: [1, 1, 1],
        t_min: 0.0,
        ..thesis_limits()
    };
    let p = plan(&axes, &ang, &lim, 1.05).unwrap();
    assert!((p.duration_s() - 1.0).abs() < 1e-4, "{}", p.duration_s());
    // below l_min
    let strict = SlewLimits {
        l_min: 0.5,
        ..thesis_limits()
    };
    assert!(matches!(
        plan(&axes, &ang, &strict, 100.0),
        Err(acs::control::slew::SlewError::BelowMinimumMomentum { axis: 0, .. })
    ));
    // no wheel on A
    let none = SlewLimits {
        wheels_per_axis: [0, 2, 2],
        ..thesis_limits()
    };
    assert!(plan(&axes, &ang, &none, 100.0).is_err());
    // NaN
    let mut bad = ang;
    bad.phi_a = f32::NAN;
    assert!(plan(&axes, &bad, &thesis_limits(), 100.0).is_err());
    // null rotation: no time, no momentum
    let zero = decompose(&Mat3::identity(), Branch::Thesis).unwrap();
    let p0 = plan(&axes, &zero, &thesis_limits(), 1.0).unwrap();
    assert_eq!(p0.duration_s(), 0.0);
}

/// The thesis's 6-tile cube: tile normals (row 3 of A0..A5, note 000 §1.2); tile 0 has no wheel.
fn cube_wheels() -> [Wheel; 5] {
    let z = [
        Vec3::new(0.0, 1.0, 0.0),  // tile 1: +V
        Vec3::new(0.0, 0.0, 1.0),  // tile 2: +W
        Vec3::new(-1.0, 0.0, 0.0), // tile 3: −U
        Vec3::new(0.0, -1.0, 0.0), // tile 4: −V
        Vec3::new(0.0, 0.0, -1.0), // tile 5: −W
    ];
    z.map(|axis_body| Wheel {
        axis_body,
        limit: 1.0,
        working: true,
    })
}

#[test]
fn cube_allocation_is_the_thesis_rule() {
    let wheels = cube_wheels();
    let l = Vec3::new(0.01, -0.02, 0.03);
    let a = allocate(&wheels, &l).unwrap();
    assert_eq!(a.rank, 3);
    // h_m = −(L·ẑ_m)/n_axis: U has one wheel (−U), V and W two
    let expected = [
        -(-0.02) / 2.0,
        -0.03 / 2.0,
        -(-0.01),
        -(0.02) / 2.0,
        -(-0.03) / 2.0,
    ];
    for (h, e) in a.wheel.iter().zip(expected) {
        assert!((h - e).abs() < 1e-8, "{:?}", a.wheel);
    }
    assert!((body_vector(&wheels, &a.wheel) - l).norm() < 1e-8);
    assert!(a.unrealised.norm() < 1e-8);
}

#[test]
fn allocation_with_failed_wheels_saturation_and_bad_input() {
    let mut wheels = cube_wheels();
    wheels[2].working = false; // the only U wheel
    let l = Vec3::new(0.01, 0.02, 0.0);
    let a = allocate(&wheels, &l).unwrap();
    assert_eq!(a.rank, 2);
    assert_eq!(a.wheel[2], 0.0);
    assert!((a.unrealised - Vec3::new(0.01, 0.0, 0.0)).norm() < 1e-7);
    // saturation keeps the direction
    let wheels = cube_wheels();
    let big = Vec3::new(3.0, -1.0, 0.5);
    let a = allocate(&wheels, &big).unwrap();
    assert!(a.scale < 1.0);
    assert!(a.wheel.iter().all(|h| h.abs() <= 1.0 + 1e-6));
    let produced = body_vector(&wheels, &a.wheel);
    assert!((produced.normalize() - big.normalize()).norm() < 1e-6);
    // errors
    assert!(allocate(&wheels, &Vec3::new(f32::NAN, 0.0, 0.0)).is_err());
    let dead = wheels.map(|w| Wheel {
        working: false,
        ..w
    });
    assert!(allocate(&dead, &big).is_err());
}

#[test]
fn hexagon_minimum_norm_versus_eq_10_30() {
    // Hexagonal prism (note 000 §1.2): side-face normals in the U–W plane at ±30°, ±90°, ±150°
    // from U, none along U; V is the prism axis with two end faces.
    let c = 30f32.to_radians().cos();
    let s = 30f32.to_radians().sin();
    let axes = [
        Vec3::new(c, 0.0, s),
        Vec3::new(c, 0.0, -s),
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(0.0, 0.0, -1.0),
        Vec3::new(-c, 0.0, s),
        Vec3::new(-c, 0.0, -s),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(0.0, -1.0, 0.0),
    ];
    let wheels = axes.map(|axis_body| Wheel {
        axis_body,
        limit: 10.0,
        working: true,
    });
    let l = Vec3::new(1.0, 0.0, 0.0);
    let a = allocate(&wheels, &l).unwrap();
    // eq. 10.30: the two adjacent faces take (L_u/2)/cos 30° = 0.57735 each
    let thesis = 0.5 / c;
    assert!((thesis - 0.57735).abs() < 1e-5);
    // minimum norm: all four faces with a U component take L_u/(4 cos 30°) = 0.2887
    for k in [0, 1] {
        assert!((a.wheel[k] + 1.0 / (4.0 * c)).abs() < 1e-6, "{:?}", a.wheel);
    }
    for k in [4, 5] {
        assert!((a.wheel[k] - 1.0 / (4.0 * c)).abs() < 1e-6, "{:?}", a.wheel);
    }
    let norm2: f32 = a.wheel.iter().map(|h| h * h).sum();
    assert!(
        (norm2 - 2.0 * thesis * thesis / 2.0).abs() < 1e-6,
        "{norm2}"
    ); // half of eq. 10.30's
    assert!((body_vector(&wheels, &a.wheel) - l).norm() < 1e-6);
}

/// The cached allocator gives exactly what `allocate` gives, detects a change of the working
/// set, and refuses what `allocate` refuses.
#[test]
fn cached_allocator_matches_allocate_and_detects_a_failure() {
    let s = 1.0 / 3.0f32.sqrt();
    let mut wheels = [
        Wheel {
            axis_body: Vec3::x(),
            limit: 1e-3,
            working: true,
        },
        Wheel {
            axis_body: Vec3::y(),
            limit: 1e-3,
            working: true,
        },
        Wheel {
            axis_body: Vec3::z(),
            limit: 1e-3,
            working: true,
        },
        Wheel {
            axis_body: Vec3::new(s, s, s),
            limit: 1e-3,
            working: true,
        },
    ];
    let cached = Allocator::new(&wheels).unwrap();
    for l in [
        Vec3::new(1e-4, -2e-4, 3e-4),
        Vec3::new(5e-3, 1e-3, -2e-3), // saturates
        Vec3::zeros(),
    ] {
        assert_eq!(
            cached.allocate(&wheels, &l).unwrap(),
            allocate(&wheels, &l).unwrap()
        );
    }
    wheels[3].working = false;
    assert!(!cached.is_for(&wheels));
    assert_eq!(
        cached.allocate(&wheels, &Vec3::x()),
        Err(WheelError::StaleAllocator)
    );
    let rebuilt = Allocator::new(&wheels).unwrap();
    let l = Vec3::new(1e-4, -2e-4, 3e-4);
    assert_eq!(
        rebuilt.allocate(&wheels, &l).unwrap(),
        allocate(&wheels, &l).unwrap()
    );
    assert_eq!(
        rebuilt.allocate(&wheels, &Vec3::new(f32::NAN, 0.0, 0.0)),
        Err(WheelError::NotFinite)
    );
    wheels[0].limit = f32::NAN;
    assert_eq!(rebuilt.allocate(&wheels, &l), Err(WheelError::NotFinite));
    for w in wheels.iter_mut() {
        w.working = false;
    }
    assert_eq!(Allocator::new(&wheels), Err(WheelError::NoWorkingWheel));
}

/// A slew about one principal axis of the flight configuration: the f32 decomposition leaves
/// ~1e-8 rad on the other axes, which the planner treats as null rotations (it refused the
/// slew with `BelowMinimumMomentum` before `NULL_ANGLE_RAD`).
#[test]
fn single_axis_slew_is_planned() {
    use acs::attitude::Quaternion;
    use acs::control::slew::{decompose, manoeuvre_matrix, plan, Branch, NULL_ANGLE_RAD};
    let cfg = &acs::flight::CONFIG;
    let q = Quaternion::new_normalize(0.094, 0.156, -0.723, 0.666).unwrap();
    let r = Quaternion::new_normalize(0.996_194_7, 0.087_155_74, 0.0, 0.0).unwrap();
    let t = q.mul(&r);
    let m = manoeuvre_matrix(&q.to_dcm(), &t.to_dcm(), &cfg.axes);
    let angles = decompose(&m, Branch::Shortest).unwrap();
    assert!(angles.theta_b.abs() <= NULL_ANGLE_RAD && angles.psi_c.abs() <= NULL_ANGLE_RAD);
    assert!(
        (angles.phi_a - 10f32.to_radians()).abs() < 1e-5,
        "{angles:?}"
    );
    let p = plan(&cfg.axes, &angles, &cfg.slew_limits, 120.0).unwrap();
    // only the rotation about A takes time
    assert_eq!(p.steps[0].duration_s, 0.0);
    assert_eq!(p.steps[1].duration_s, 0.0);
    assert!(p.steps[2].duration_s > 0.0);
}
