//! Tests of `acs::planning` (seed 001, note 001): kinematics round trips and a known rotation,
//! scalar-last conversion, the clamped spline against polynomials and the note's worked example,
//! the allocation identities, and the feasibility flags.
//!
//! Figures: `cargo test --test planning -- --nocapture`.

use acs::attitude::{Euler321, Quaternion};
use acs::control::wheels::Wheel;
use acs::linalg::{Mat3, Vec3};
use acs::planning::allocation::{hybrid, magnetic, DipoleSaturation};
use acs::planning::feasibility::{check, Limits};
use acs::planning::kinematics::{
    body_acceleration, body_rate, complete_from_vector_part, from_scalar_last, quaternion_rate,
    to_scalar_last,
};
use acs::planning::spline::{AttitudeSpline, ClampedSpline};
use acs::planning::PlanningError;

mod figures;
use figures::figure;

fn quat_f64_const_rate(q0: [f64; 4], w: [f64; 3], t: f64) -> [f64; 4] {
    // q(t) = q0 ⊗ (cos(|w|t/2), ŵ sin(|w|t/2)) solves q̇ = ½ q ⊗ (0, ω) for constant body ω
    let n = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
    let (s, c) = (0.5 * n * t).sin_cos();
    let r = [c, w[0] / n * s, w[1] / n * s, w[2] / n * s];
    let p = q0;
    [
        p[0] * r[0] - p[1] * r[1] - p[2] * r[2] - p[3] * r[3],
        p[1] * r[0] + p[2] * r[3] - p[3] * r[2] + p[0] * r[1],
        -p[1] * r[3] + p[2] * r[0] + p[3] * r[1] + p[0] * r[2],
        p[1] * r[2] - p[2] * r[1] + p[3] * r[0] + p[0] * r[3],
    ]
}

fn q32(q: [f64; 4]) -> Quaternion {
    Quaternion {
        q0: q[0] as f32,
        q1: q[1] as f32,
        q2: q[2] as f32,
        q3: q[3] as f32,
    }
}

#[test]
fn kinematics_scalar_last_conversion_and_euler_vector() {
    // note 001 §1.6/§7 item 1: ZYX (ψ, θ, φ) = (30°, 35°, 40°) gives, scalar LAST,
    // (0.24194098, 0.35736694, 0.13261083, 0.89228236)
    let thesis = [0.24194098f32, 0.35736694, 0.13261083, 0.89228236];
    let q = from_scalar_last(thesis);
    let crate_q = Quaternion::from_dcm(&acs::attitude::Dcm::from_euler_321(&Euler321 {
        psi_rad: 30f32.to_radians(),
        theta_rad: 35f32.to_radians(),
        phi_rad: 40f32.to_radians(),
    }))
    .canonical();
    let err = [
        q.q0 - crate_q.q0,
        q.q1 - crate_q.q1,
        q.q2 - crate_q.q2,
        q.q3 - crate_q.q3,
    ];
    figure(
        "planning.thesis_q",
        err.iter().fold(0.0f64, |m, e| m.max(f64::from(e.abs()))),
    );
    println!("kinematics: thesis (6.1a) vs crate Euler321: {err:?}");
    assert!(err.iter().all(|e| e.abs() < 2e-6));
    assert_eq!(to_scalar_last(&q), thesis);
    // rotation angle 53.6777° (note 001 §1.6)
    let angle = q.angle_to(&Quaternion::IDENTITY).to_degrees();
    assert!((angle - 53.6777).abs() < 1e-3, "{angle}");
    // same attitude matrix: thesis eq. 2.8 element A12 = 2(q1q2 + q3q4)
    let a = q.to_dcm();
    let [q1, q2, q3, q4] = thesis;
    assert!((a.matrix().m12 - 2.0 * (q1 * q2 + q3 * q4)).abs() < 1e-6);
    assert!((a.matrix().m31 - 2.0 * (q1 * q3 + q2 * q4)).abs() < 1e-6);
}

#[test]
fn kinematics_round_trip_and_known_rotation() {
    let mut max_rt = 0.0f32;
    let mut max_fd = 0.0f64;
    let cases = [
        (
            [0.89228236, 0.24194098, 0.35736694, 0.13261083],
            [0.01, -0.02, 0.03],
        ),
        ([1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.1]),
        ([0.5, -0.5, 0.5, 0.5], [-0.3, 0.2, 0.05]),
        ([0.0, 0.6, 0.0, 0.8], [1e-3, 2e-3, -1e-3]),
    ];
    for (q0, w) in cases {
        let q = q32(q0);
        let w32 = Vec3::new(w[0] as f32, w[1] as f32, w[2] as f32);
        let qd = quaternion_rate(&q, &w32);
        let back = body_rate(&q, &qd).unwrap();
        max_rt = max_rt.max((back - w32).norm() / w32.norm());
        // known rotation: f64 central difference of the exact solution
        let h = 1e-3;
        let qp = quat_f64_const_rate(q0, w, h);
        let qm = quat_f64_const_rate(q0, w, -h);
        let fd: Vec<f64> = (0..4).map(|i| (qp[i] - qm[i]) / (2.0 * h)).collect();
        let qd_fd = q32([fd[0], fd[1], fd[2], fd[3]]);
        let w_fd = body_rate(&q, &qd_fd).unwrap();
        max_fd = max_fd.max(((w_fd - w32).norm() / w32.norm()) as f64);
        // constant rate: q̈ = ½ q̇ ⊗ (0, ω) and ω̇ = 0
        let qdd = quaternion_rate(&qd, &w32);
        let wdot = body_acceleration(&q, &qdd).unwrap();
        assert!(wdot.norm() < 1e-6 * w32.norm().max(1e-3), "{wdot}");
        // dA/dt = −[ω×]A (note 001 §1.4)
        let dt = 1e-2;
        let a_p = q32(quat_f64_const_rate(q0, w, dt)).to_dcm();
        let a_m = q32(quat_f64_const_rate(q0, w, -dt)).to_dcm();
        let a_dot = (a_p.matrix() - a_m.matrix()) / (2.0 * dt as f32);
        let expect = -w32.cross_matrix() * q.to_dcm().matrix();
        assert!((a_dot - expect).norm() < 2e-4 * w32.norm().max(1e-2) + 1e-4);
    }
    figure("planning.round_trip_rel", max_rt);
    figure("planning.finite_difference_rel", max_fd);
    println!("kinematics: round trip max rel {max_rt:e}; vs f64 finite difference {max_fd:e}");
    assert!(max_rt < 4e-7);
    assert!(max_fd < 1e-6);
}

#[test]
fn kinematics_errors_and_vector_part() {
    let bad = Quaternion {
        q0: 2.0,
        q1: 0.0,
        q2: 0.0,
        q3: 0.0,
    };
    assert!(matches!(
        body_rate(&bad, &bad),
        Err(PlanningError::NotUnit(_))
    ));
    let nan = Quaternion {
        q0: f32::NAN,
        ..Quaternion::IDENTITY
    };
    assert_eq!(body_rate(&nan, &nan), Err(PlanningError::NotFinite));
    assert!(matches!(
        complete_from_vector_part(&Vec3::new(1.0, 0.1, 0.0), &Vec3::zeros(), &Vec3::zeros()),
        Err(PlanningError::VectorPartTooLong(_))
    ));
    // vector-part completion agrees with the full kinematics along a constant-rate rotation
    let q0 = [0.89228236, 0.24194098, 0.35736694, 0.13261083];
    let w = [0.01, -0.02, 0.03];
    let q = quat_f64_const_rate(q0, w, 10.0);
    let w32 = Vec3::new(0.01, -0.02, 0.03);
    let qf = q32(q);
    let qd = quaternion_rate(&qf, &w32);
    let qdd = quaternion_rate(&qd, &w32);
    let jet = complete_from_vector_part(
        &Vec3::new(qf.q1, qf.q2, qf.q3),
        &Vec3::new(qd.q1, qd.q2, qd.q3),
        &Vec3::new(qdd.q1, qdd.q2, qdd.q3),
    )
    .unwrap();
    assert!((jet.q.q0 - qf.q0).abs() < 1e-6);
    assert!((jet.q_dot.q0 - qd.q0).abs() < 1e-7);
    assert!((jet.q_ddot.q0 - qdd.q0).abs() < 1e-7);
}

#[test]
fn spline_reproduces_a_cubic() {
    // y = 0.3 − 2e-4 t + 3e-7 t² − 1e-10 t³ on uneven knots over 1500 s, clamped with ẏ
    let y = |t: f64| 0.3 - 2e-4 * t + 3e-7 * t * t - 1e-10 * t * t * t;
    let yd = |t: f64| -2e-4 + 6e-7 * t - 3e-10 * t * t;
    let ydd = |t: f64| 6e-7 - 6e-10 * t;
    let knots = [0.0f32, 200.0, 500.0, 900.0, 1000.0, 1500.0];
    let vals: Vec<f32> = knots.iter().map(|t| y(*t as f64) as f32).collect();
    let s: ClampedSpline<8> =
        ClampedSpline::new(&knots, &vals, yd(0.0) as f32, yd(1500.0) as f32).unwrap();
    let (mut e0, mut e1, mut e2) = (0.0f64, 0.0f64, 0.0f64);
    for i in 0..=300 {
        let t = i as f64 * 5.0;
        let p = s.eval(t as f32).unwrap();
        e0 = e0.max((p.value as f64 - y(t)).abs());
        e1 = e1.max((p.d1 as f64 - yd(t)).abs());
        e2 = e2.max((p.d2 as f64 - ydd(t)).abs());
    }
    figure("planning.spline_cubic.value", e0);
    figure("planning.spline_cubic.d1_rel", e1 / 2e-4);
    figure("planning.spline_cubic.d2_rel", e2 / 6e-7);
    println!("spline cubic: max err value {e0:e}, d1 {e1:e} (scale 2e-4), d2 {e2:e} (scale 6e-7)");
    assert!(e0 < 1e-6);
    assert!(e1 < 2e-4 * 1e-5);
    assert!(e2 < 6e-7 * 1e-4);
}

#[test]
fn spline_worked_example_note_001() {
    // note 001 §3.6 worked example (checked there against scipy CubicSpline clamped):
    // t = [0, 500, 1000, 1500], q = [0.24194, 0.1, 0.05, 0.0], v1 = v4 = 0
    let s: ClampedSpline<4> = ClampedSpline::new(
        &[0.0, 500.0, 1000.0, 1500.0],
        &[0.24194, 0.1, 0.05, 0.0],
        0.0,
        0.0,
    )
    .unwrap();
    let expected = [
        [0.24194, 0.0, -1.169072e-6, 1.202624e-9],
        [0.1, -2.67104e-4, 6.34864e-7, -6.01312e-10],
        [0.05, -8.32240e-5, -2.67104e-7, 4.67104e-10],
    ];
    let mut worst = 0.0f32;
    for (k, row) in expected.iter().enumerate() {
        let got = s.segment(k).unwrap();
        for (g, e) in got.iter().zip(row.iter()) {
            let rel = if *e == 0.0 {
                g.abs()
            } else {
                (g - e).abs() / e.abs()
            };
            worst = worst.max(rel);
        }
    }
    figure("planning.spline_example_rel", worst);
    println!("spline worked example: worst relative coefficient error {worst:e}");
    // the note prints 7 significant digits
    assert!(worst < 1e-6, "{worst}");
    assert!(s.segment(3).is_none());
}

#[test]
fn spline_errors() {
    assert_eq!(
        ClampedSpline::<4>::new(&[0.0], &[1.0], 0.0, 0.0),
        Err(PlanningError::KnotCount(1))
    );
    assert_eq!(
        ClampedSpline::<2>::new(&[0.0, 1.0, 2.0], &[1.0, 2.0, 3.0], 0.0, 0.0),
        Err(PlanningError::KnotCount(3))
    );
    assert_eq!(
        ClampedSpline::<4>::new(&[0.0, 1.0, 1.0], &[1.0, 2.0, 3.0], 0.0, 0.0),
        Err(PlanningError::KnotsNotIncreasing(2))
    );
    assert_eq!(
        ClampedSpline::<4>::new(&[0.0, f32::NAN], &[1.0, 2.0], 0.0, 0.0),
        Err(PlanningError::NotFinite)
    );
    let s = ClampedSpline::<4>::new(&[0.0, 1.0], &[1.0, 2.0], 0.0, 0.0).unwrap();
    assert_eq!(s.eval(1.5), Err(PlanningError::OutOfRange(1.5)));
    assert!(s.eval(f32::NAN).is_err());
    // two knots, clamped at zero: the smoothstep 1 + 3t² − 2t³
    let p = s.eval(0.5).unwrap();
    assert!((p.value - 1.5).abs() < 1e-7 && (p.d1 - 1.5).abs() < 1e-6);
}

fn thesis_initial() -> Quaternion {
    from_scalar_last([0.24194098, 0.35736694, 0.13261083, 0.89228236])
}

fn rest_to_rest(tf: f32) -> AttitudeSpline<8> {
    // the note's interior knots of its 150 s optimum are not needed here: a straight line in q_v
    let qi = thesis_initial();
    let knots = [0.0, tf / 3.0, 2.0 * tf / 3.0, tf];
    let qs: Vec<Quaternion> = [1.0f32, 2.0 / 3.0, 1.0 / 3.0, 0.0]
        .iter()
        .map(|f| {
            let v = Vec3::new(qi.q1, qi.q2, qi.q3) * *f;
            Quaternion {
                q0: (1.0 - v.norm_squared()).sqrt(),
                q1: v.x,
                q2: v.y,
                q3: v.z,
            }
        })
        .collect();
    AttitudeSpline::new(&knots, &qs, &Vec3::zeros(), &Vec3::zeros()).unwrap()
}

#[test]
fn attitude_spline_ends_and_rates() {
    let p = rest_to_rest(150.0);
    let s0 = p.sample(0.0).unwrap();
    let s1 = p.sample(150.0).unwrap();
    assert!(s0.omega_radps.norm() < 1e-9 && s1.omega_radps.norm() < 1e-9);
    assert!(s0.jet.q.angle_to(&thesis_initial()) < 1e-3);
    assert!(s1.jet.q.angle_to(&Quaternion::IDENTITY) < 1e-6);
    // ω from the spline agrees with a central difference of the attitude
    let (t, h) = (60.0f32, 0.05f32);
    let s = p.sample(t).unwrap();
    let (qp, qm) = (
        p.sample(t + h).unwrap().jet.q,
        p.sample(t - h).unwrap().jet.q,
    );
    let d = qm.conjugate().mul(&qp); // body-frame increment q(t−h)* ⊗ q(t+h)
    let w_fd = Vec3::new(d.q1, d.q2, d.q3) * (2.0 / (2.0 * h));
    println!(
        "attitude spline: ω {} vs finite difference {} (rad/s)",
        s.omega_radps, w_fd
    );
    assert!((w_fd - s.omega_radps).norm() < 1e-3 * s.omega_radps.norm());
}

fn b_ref_nt() -> Vec3 {
    // note 001 §1.9, t = 150 s, converted to nT
    Vec3::new(-11087.1, -5888.94, 22666.8)
}

#[test]
fn allocation_identities() {
    let b = b_ref_nt();
    let tau = Vec3::new(1e-4, -2e-4, 3e-5);
    let m_max = Vec3::new(10.0, 10.0, 10.0);
    let a = magnetic(&tau, &b, &m_max, DipoleSaturation::PerAxisClip).unwrap();
    // note 001 §7 item 4: m × b = τ − b̂(b̂·τ); lost part is along b; the sum gives τ back
    let bh = b.normalize();
    assert!((a.torque_nm + a.lost_along_b_nm - tau).norm() < 1e-6 * tau.norm());
    assert!(a.lost_along_b_nm.cross(&bh).norm() < 1e-6 * tau.norm());
    assert!(a.torque_nm.dot(&bh).abs() < 1e-6 * tau.norm());
    assert!(a.dipole_am2.dot(&bh).abs() < 1e-5 * a.dipole_am2.norm());
    assert!(a.saturation_ratio < 1.0);
    // a torque along b is lost entirely
    let along = magnetic(&(bh * 1e-4), &b, &m_max, DipoleSaturation::KeepDirection).unwrap();
    assert!(along.torque_nm.norm() < 1e-9 && (along.lost_along_b_nm - bh * 1e-4).norm() < 1e-9);
    // saturation: per-axis clip vs direction-keeping
    let big = Vec3::new(3e-3, -1e-3, 2e-3);
    let clip = magnetic(&big, &b, &m_max, DipoleSaturation::PerAxisClip).unwrap();
    let keep = magnetic(&big, &b, &m_max, DipoleSaturation::KeepDirection).unwrap();
    assert!(clip.saturation_ratio > 1.0);
    assert!(clip.dipole_am2.amax() <= 10.0 && keep.dipole_am2.amax() <= 10.0 + 1e-4);
    let ach = big - keep.lost_along_b_nm;
    assert!(keep.torque_nm.normalize().dot(&ach.normalize()) > 1.0 - 1e-6);
    // errors
    assert_eq!(
        magnetic(&tau, &Vec3::zeros(), &m_max, DipoleSaturation::PerAxisClip),
        Err(PlanningError::WeakField(0.0))
    );
    assert_eq!(
        magnetic(
            &tau,
            &b,
            &Vec3::new(1.0, 0.0, 1.0),
            DipoleSaturation::PerAxisClip
        ),
        Err(PlanningError::InvalidParameter)
    );
}

fn thesis_wheels(limit: f32) -> [Wheel; 3] {
    [Vec3::x(), Vec3::y(), Vec3::z()].map(|a| Wheel {
        axis_body: a,
        limit,
        working: true,
    })
}

#[test]
fn hybrid_allocation_delivers_the_torque() {
    let b = b_ref_nt();
    let m_max = Vec3::new(10.0, 10.0, 10.0);
    let tau = Vec3::new(1e-4, -2e-4, 3e-4);
    let w = Vec3::new(0.01, 0.0, -0.02);
    let h = Vec3::new(1e-3, 2e-3, -1e-3);
    let a = hybrid(
        &tau,
        &b,
        &m_max,
        DipoleSaturation::PerAxisClip,
        &thesis_wheels(0.01),
        &h,
        &w,
    )
    .unwrap();
    println!("hybrid: shortfall {:e} N·m", a.shortfall_nm.norm());
    assert!(a.shortfall_nm.norm() < 1e-9);
    assert_eq!(a.wheel_scale, 1.0);
    // wheels supply exactly the lost part plus the gyroscopic term: ḣ = −τ_lost − ω × h
    let hdot = Vec3::from(a.wheel_torque_nm);
    assert!((hdot + a.magnetic.lost_along_b_nm + w.cross(&h)).norm() < 1e-9);
    // wheel torque limit: scaled, shortfall reported
    let sat = hybrid(
        &(b.normalize() * 0.05),
        &b,
        &m_max,
        DipoleSaturation::PerAxisClip,
        &thesis_wheels(0.01),
        &Vec3::zeros(),
        &Vec3::zeros(),
    )
    .unwrap();
    assert!(sat.wheel_scale < 1.0 && sat.shortfall_nm.norm() > 0.01);
}

#[test]
fn feasibility_flags() {
    let inertia = Mat3::from_diagonal_element(0.7); // note 001 §4 Table 6.2
    let field = |_t: f32| b_ref_nt();
    // magnetorquers only, 1500 s: no saturation, but torque lost along b is reported
    let mag_only: Limits<0> = Limits {
        m_max_am2: Vec3::new(10.0, 10.0, 10.0),
        saturation: DipoleSaturation::PerAxisClip,
        wheels: [],
        wheel_momentum_max: [],
    };
    let slow = check(&rest_to_rest(1500.0), &inertia, field, &mag_only, &[], 300).unwrap();
    println!("feasibility 1500 s MT only: {slow:?}");
    assert!(!slow.dipole_saturated());
    assert!(slow.lost_torque_integral > 0.0 && slow.max_lost_fraction > 0.0);
    assert!(slow.max_shortfall_nm > 0.0);
    // 150 s is 100× the torque: saturates the coils
    let fast = check(&rest_to_rest(150.0), &inertia, field, &mag_only, &[], 300).unwrap();
    println!("feasibility 150 s MT only: {fast:?}");
    assert!(fast.max_torque_nm > 90.0 * slow.max_torque_nm);
    assert!(fast.dipole_saturated() && fast.max_shortfall_nm > slow.max_shortfall_nm);
    // with the thesis's wheels (0.01 N·m, 5000 rpm × 8e-4 kg·m²): feasible, no shortfall
    let h_max = 8e-4 * 5000.0 * core::f32::consts::PI / 30.0;
    let hybrid_limits: Limits<3> = Limits {
        m_max_am2: Vec3::new(10.0, 10.0, 10.0),
        saturation: DipoleSaturation::PerAxisClip,
        wheels: thesis_wheels(0.01),
        wheel_momentum_max: [h_max; 3],
    };
    let rw = check(
        &rest_to_rest(150.0),
        &inertia,
        field,
        &hybrid_limits,
        &[0.0; 3],
        300,
    )
    .unwrap();
    println!("feasibility 150 s MT+RW: {rw:?}");
    assert!(!rw.wheel_torque_exceeded() && !rw.wheel_speed_exceeded());
    assert!(rw.max_wheel_torque_ratio > 0.0 && rw.max_wheel_torque_ratio < 0.1);
    assert!(rw.max_shortfall_nm < 1e-4 * rw.max_torque_nm);
    // tiny wheels: both limits flagged
    let tiny: Limits<3> = Limits {
        wheels: thesis_wheels(1e-6),
        wheel_momentum_max: [1e-6; 3],
        ..hybrid_limits
    };
    let bad = check(&rest_to_rest(150.0), &inertia, field, &tiny, &[0.0; 3], 300).unwrap();
    assert!(bad.wheel_torque_exceeded() && bad.wheel_speed_exceeded());
    assert!(bad.max_shortfall_nm > 0.0);
    assert_eq!(
        check(&rest_to_rest(150.0), &inertia, field, &tiny, &[0.0; 3], 0),
        Err(PlanningError::InvalidParameter)
    );
}
