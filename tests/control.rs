//! Control: principal axes, slew decomposition and planning, wheel allocation, against the
//! thesis's numbers (note 000 §4.2–4.4, §4.8; data in tests/data/thesis_control.txt).

use std::collections::HashMap;

mod common;
mod figures;
use figures::figure;

use acs::attitude::Dcm;
use acs::control::principal_axes::{principal_axes, PrincipalAxes, PrincipalAxesError};
use acs::control::slew::{decompose, manoeuvre_matrix, plan, step_for, Branch, SlewLimits};
use acs::control::wheels::{allocate, body_vector, Allocator, Wheel, WheelError, RANK_TOLERANCE};
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
    figure("control.principal_axes.e", e_err);
    figure("control.principal_axes.moments_rel", m_err);
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
    figure("control.chapter_10.angles_rel", worst);
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
        let l = rel(&s.h_body(&axes), &vec3(&d, momenta[k]));
        let t = rel(&(s.h_body(&axes) / 1e-4), &vec3(&d, torques[k]));
        figure(&format!("control.chapter_10.step{k}_rel"), w.max(l).max(t));
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
        rel(&p.steps[0].h_body(&axes), &vec3(d, &format!("{prefix}_l3"))),
        rel(&p.steps[1].h_body(&axes), &vec3(d, &format!("{prefix}_l2"))),
        rel(&p.steps[2].h_body(&axes), &vec3(d, &format!("{prefix}_l1"))),
    ];
    figure(
        &format!("control.{prefix}_rel"),
        l_err.iter().fold(angle_err, |m, e| m.max(*e)),
    );
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

/// Worst errors of the allocator against f64, by rank of the working set.
#[derive(Default)]
struct AllocatorErrors {
    /// Subsets checked, by rank.
    count: [usize; 4],
    /// `(W Wᵀ)⁺`: max-entry error relative to the largest entry.
    operator: [f64; 4],
    /// Wheel commands: `|h − h₆₄|/(|L|·‖W⁺‖)`.
    wheel: [f64; 4],
    /// `|unrealised − unrealised₆₄|/|L|`.
    unrealised: [f64; 4],
    /// The part of `h` in the null space of `W` (zero for the minimum-norm solution):
    /// `|h − W⁺W h|/(|L|·‖W⁺‖)`.
    null_part: [f64; 4],
    /// The largest threshold at which a working set would have one rank more than its exact
    /// one (`common::critical_tol`: its f32 rounding noise), and the smallest one at which it
    /// would have one rank less.
    noise: f64,
    margin: f64,
}

/// Checks `Allocator::new` and `allocate` against the f64 minimum-norm allocation for each
/// working set `masks` of the wheels with axes `axes` (`has_wheel[i]`: slot `i` has one).
fn allocator_against_f64<const N: usize>(
    axes: [Vec3; N],
    has_wheel: [bool; N],
    masks: &[u32],
    seed: &mut u64,
    errors: &mut AllocatorErrors,
) {
    let mut uniform = || {
        *seed ^= *seed << 13;
        *seed ^= *seed >> 7;
        *seed ^= *seed << 17;
        (*seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for &mask in masks {
        let working: [bool; N] = core::array::from_fn(|i| has_wheel[i] && mask & (1 << i) != 0);
        if !working.iter().any(|w| *w) {
            continue;
        }
        // limits far above the commands: no saturation
        let wheels: [Wheel; N] = core::array::from_fn(|i| Wheel {
            axis_body: axes[i],
            limit: 1.0,
            working: working[i],
        });
        let allocator = Allocator::new(&wheels).unwrap();
        // f64: W (3×N, zero columns for idle slots), G = W Wᵀ, G⁺
        let w64 = nalgebra::SMatrix::<f64, 3, N>::from_fn(|r, c| {
            if working[c] {
                f64::from(axes[c][r])
            } else {
                0.0
            }
        });
        let g64 = w64 * w64.transpose();
        let (p64, rank) = common::pinv_sym64(&g64);
        assert_eq!(allocator.rank(), rank, "mask {mask:b}");
        let r = usize::from(rank);
        let mut gram32 = acs::linalg::SymMat3::zeros();
        for (a, w) in axes.iter().zip(working) {
            if w {
                gram32.add_outer(a);
            }
        }
        if rank < 3 {
            errors.noise = errors.noise.max(common::critical_tol(&gram32, rank + 1));
        }
        errors.margin = errors.margin.min(common::critical_tol(&gram32, rank));
        errors.count[r] += 1;
        let p32 = allocator.pseudoinverse().to_mat3().map(f64::from);
        errors.operator[r] = errors.operator[r].max((p32 - p64).amax() / p64.amax());
        // ‖W⁺‖ = √‖G⁺‖₂
        let w_pinv_norm = common::eigenvalues_sym64(&p64)[0].sqrt();
        for _ in 0..4 {
            let l64 = nalgebra::Vector3::new(uniform(), uniform(), uniform()) * 1e-3;
            let l = l64.map(|x| x as f32);
            let l64 = l.map(f64::from);
            let a = allocator.allocate(&wheels, &l).unwrap();
            assert_eq!(a.scale, 1.0);
            assert_eq!(a, allocate(&wheels, &l).unwrap());
            let h64 = -(w64.transpose() * (p64 * l64));
            let u64 = l64 - g64 * (p64 * l64);
            let h32 = nalgebra::SVector::<f64, N>::from_fn(|i, _| f64::from(a.wheel[i]));
            let scale = l64.norm() * w_pinv_norm;
            errors.wheel[r] = errors.wheel[r].max((h32 - h64).norm() / scale);
            let u32_ = a.unrealised.map(f64::from);
            errors.unrealised[r] = errors.unrealised[r].max((u32_ - u64).norm() / l64.norm());
            let range_part = w64.transpose() * (p64 * (w64 * h32));
            errors.null_part[r] = errors.null_part[r].max((h32 - range_part).norm() / scale);
            for (h, w) in a.wheel.iter().zip(working) {
                if !w {
                    assert_eq!(*h, 0.0);
                }
            }
        }
    }
}

/// The allocator's closed-form `(W Wᵀ)⁺` (`linalg::pseudoinverse`) against the f64
/// minimum-norm allocation of the same f32 axes, on every preset of `acs::tiles` with every
/// non-empty working set of wheels (rank 3, 2 and 1: failed wheels), and the flight
/// configuration's coils: the rank is the f64 one, and the operator, the wheel commands, the
/// unrealised part and the null-space part of the commands (the minimum-norm property) stay
/// within the bounds of the `control::wheels` module docs.
#[test]
fn allocator_against_f64_on_every_wheel_subset() {
    let mut errors = AllocatorErrors {
        margin: 1.0,
        ..Default::default()
    };
    let mut seed = 0x9E37_79B9_7F4A_7C15u64;
    fn axes<const N: usize>(tiles: &[acs::tiles::Tile]) -> ([Vec3; N], [bool; N]) {
        (
            core::array::from_fn(|i| tiles[i].normal_body()),
            core::array::from_fn(|i| tiles[i].has_working_wheel()),
        )
    }
    let t = acs::tiles::cube_thesis();
    let (a, w) = axes::<6>(&t);
    allocator_against_f64(a, w, &common::tile_subsets(&t), &mut seed, &mut errors);
    let t = acs::tiles::cube_4_per_face();
    let (a, w) = axes::<24>(&t);
    allocator_against_f64(a, w, &common::tile_subsets(&t), &mut seed, &mut errors);
    let t = acs::tiles::hexagonal_prism();
    let (a, w) = axes::<8>(&t);
    allocator_against_f64(a, w, &common::tile_subsets(&t), &mut seed, &mut errors);
    let t = acs::tiles::octagonal_prism();
    let (a, w) = axes::<10>(&t);
    allocator_against_f64(a, w, &common::tile_subsets(&t), &mut seed, &mut errors);
    let coils = &acs::flight::CONFIG.coils;
    let coil_axes: [Vec3; 3] = core::array::from_fn(|i| coils[i].axis_body);
    allocator_against_f64(
        coil_axes,
        [true; 3],
        &[1, 2, 3, 4, 5, 6, 7],
        &mut seed,
        &mut errors,
    );
    // a set of the 4-per-face cube stands for every set with the same count per face
    // (`common::tile_subsets`): the operator is bit-identical
    let t = acs::tiles::cube_4_per_face();
    let (a, _) = axes::<24>(&t);
    let build = |mask: u32| {
        let wheels: [Wheel; 24] = core::array::from_fn(|i| Wheel {
            axis_body: a[i],
            limit: 1.0,
            working: mask & (1 << i) != 0,
        });
        let alloc = Allocator::new(&wheels).unwrap();
        (*alloc.pseudoinverse(), alloc.rank())
    };
    for (any, canonical) in [
        (
            0b1010_0000_0110_0001_0100_1000u32,
            0b0011_0000_0011_0001_0001_0001u32,
        ),
        (
            0b1111_1000_0100_0010_0001_0110,
            0b1111_0001_0001_0001_0001_0011,
        ),
    ] {
        assert_eq!(build(any), build(canonical));
    }
    for r in 1..=3 {
        println!(
            "allocator vs f64, rank {r}: {} working sets; (W Wᵀ)⁺ {:.2e}, wheels {:.2e}, \
             unrealised {:.2e}, null-space part {:.2e}",
            errors.count[r],
            errors.operator[r],
            errors.wheel[r],
            errors.unrealised[r],
            errors.null_part[r]
        );
    }
    println!(
        "allocator: rank decided the same for any threshold in [{:.1e}, {:.1e}]",
        errors.noise, errors.margin
    );
    assert!(
        errors.noise < RANK_TOLERANCE as f64 / 10.0 && errors.margin > RANK_TOLERANCE as f64 * 10.0
    );
    assert_eq!(errors.count[0], 0);
    assert!(errors.count[1] > 0 && errors.count[2] > 0 && errors.count[3] > 0);
    // the bounds of the `control::wheels` module docs, by rank 1, 2, 3
    for (what, measured, bound) in [
        ("operator", errors.operator, [1.2e-7, 2.4e-7, 2.3e-7]),
        ("wheels", errors.wheel, [1.3e-7, 2.5e-7, 2.2e-7]),
        ("unrealised", errors.unrealised, [1.4e-7, 4.9e-7, 3.8e-7]),
        (
            "null-space part",
            errors.null_part,
            [3.6e-8, 4.8e-8, 6.0e-8],
        ),
    ] {
        for r in 1..=3 {
            assert!(
                measured[r] <= bound[r - 1],
                "{what} rank {r}: {:e}",
                measured[r]
            );
        }
    }
}
