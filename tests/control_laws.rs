//! Closed-loop laws on their own: signs, units, saturation, degenerate field, zero rates, NaN.

mod figures;

use acs::attitude::{Dcm, Quaternion};
use acs::control::bdot::{bdot_from_rates, BdotConfig, BdotState};
use acs::control::magnetorquer::{
    coil_currents, dipole_for_torque, dipole_two_coil_xy, dipole_two_coil_xz, dumping_dipole,
    dumping_dipole_to_zero, project_torque, saturate_dipole, torque_of_dipole, MagnetorquerError,
};
use acs::control::sun_safe::{sun_safe_torque, SunSafeGains};
use acs::control::tracking::{attitude_error, tracking_torque, TrackingGains};
use acs::linalg::{Mat3, Vec3};

/// A small deterministic generator (xorshift) for property tests.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0
    }
    fn vec(&mut self, scale: f32) -> Vec3 {
        Vec3::new(self.next(), self.next(), self.next()) * scale
    }
}

#[test]
fn projection_law_properties() {
    let mut rng = Rng(0x1234_5678);
    for _ in 0..1000 {
        let tau = rng.vec(1e-5);
        let b = rng.vec(50_000.0) + Vec3::new(200.0, 0.0, 0.0);
        let m = dipole_for_torque(&tau, &b).unwrap();
        let produced = torque_of_dipole(&m, &b);
        let projected = project_torque(&tau, &b).unwrap();
        // m ⟂ B and m × B = projected torque
        assert!(m.dot(&b).abs() <= 1e-5 * m.norm() * b.norm(), "m·B");
        assert!((produced - projected).norm() <= 1e-5 * tau.norm() + 1e-12);
    }
}

#[test]
fn projection_law_degenerate_inputs() {
    let tau = Vec3::new(1e-6, 0.0, 0.0);
    assert!(matches!(
        dipole_for_torque(&tau, &Vec3::zeros()),
        Err(MagnetorquerError::WeakField(_))
    ));
    assert!(matches!(
        dipole_for_torque(&tau, &Vec3::new(f32::NAN, 1e4, 0.0)),
        Err(MagnetorquerError::NotFinite)
    ));
    // a torque along B cannot be produced: zero dipole
    let b = Vec3::new(30_000.0, 0.0, 0.0);
    assert_eq!(dipole_for_torque(&tau, &b).unwrap(), Vec3::zeros());
    // zero torque: zero dipole
    assert_eq!(
        dipole_for_torque(&Vec3::zeros(), &b).unwrap(),
        Vec3::zeros()
    );
}

#[test]
fn two_coil_laws_produce_the_commanded_components() {
    let b = Vec3::new(12_000.0, -21_000.0, 35_000.0);
    let tau = Vec3::new(2e-6, -1e-6, 3e-6);
    // thesis law: coils x and z, torque on x and z exact, residual on y
    let (m, res_y) = dipole_two_coil_xz(&tau, &b).unwrap();
    assert_eq!(m.y, 0.0);
    let t = torque_of_dipole(&m, &b);
    assert!((t.x - tau.x).abs() < 1e-12 && (t.z - tau.z).abs() < 1e-12);
    assert!((t.y - res_y).abs() < 1e-12);
    // AtmoCube law: coils x and y, torque on x and y exact, residual on z
    let (m, res_z) = dipole_two_coil_xy(&tau, &b).unwrap();
    assert_eq!(m.z, 0.0);
    let t = torque_of_dipole(&m, &b);
    assert!((t.x - tau.x).abs() < 1e-12 && (t.y - tau.y).abs() < 1e-12);
    assert!((t.z - res_z).abs() < 1e-12);
    // singular components
    assert!(dipole_two_coil_xz(&tau, &Vec3::new(3e4, 0.0, 3e4)).is_err());
    assert!(dipole_two_coil_xy(&tau, &Vec3::new(3e4, 3e4, 10.0)).is_err());
}

#[test]
fn saturation_keeps_direction_and_currents() {
    let m = Vec3::new(0.5, -0.2, 0.1);
    let (s, k) = saturate_dipole(&m, &Vec3::new(0.2, 0.2, 0.2)).unwrap();
    assert!((k - 0.4).abs() < 1e-6);
    assert!((s.normalize() - m.normalize()).norm() < 1e-6);
    assert!(s.iter().all(|x| x.abs() <= 0.2 + 1e-7));
    let (u, k) = saturate_dipole(&Vec3::new(0.1, 0.0, 0.0), &Vec3::new(0.2, 0.2, 0.2)).unwrap();
    assert_eq!((u, k), (Vec3::new(0.1, 0.0, 0.0), 1.0));
    assert!(saturate_dipole(&m, &Vec3::new(0.0, 1.0, 1.0)).is_err());
    // I = M / (N A): 34 turns, 85 mm square (note 002 §6.4), 0.319 A·m² -> 1.30 A
    let i = coil_currents(&Vec3::new(0.319, 0.0, 0.0), 34.0, 7.225e-3).unwrap();
    assert!((i.x - 1.2986).abs() < 1e-3, "{}", i.x);
    assert!(coil_currents(&m, 0.0, 1.0).is_err());
}

#[test]
fn bdot_never_adds_rotational_energy() {
    let mut rng = Rng(42);
    let config = BdotConfig {
        gain: 1e4,
        max_dipole_am2: Vec3::new(0.2, 0.2, 0.2),
    };
    for _ in 0..2000 {
        let w = rng.vec(0.3);
        let b = rng.vec(45_000.0);
        let m = bdot_from_rates(&config, &w, &b).unwrap();
        let tau = torque_of_dipole(&m, &(b));
        assert!(w.dot(&tau) <= 1e-12, "{}", w.dot(&tau));
    }
    // zero rate: zero dipole
    let m = bdot_from_rates(&config, &Vec3::zeros(), &Vec3::new(1e4, 2e4, 3e4)).unwrap();
    assert_eq!(m, Vec3::zeros());
    assert!(bdot_from_rates(&config, &Vec3::new(f32::NAN, 0.0, 0.0), &Vec3::x()).is_err());
}

#[test]
fn bdot_magnetometer_form_matches_gyro_form_and_handles_first_sample() {
    // body spinning at ω in a constant inertial field: B_body(t) = A(t) B_inertial
    let config = BdotConfig {
        gain: 1e4,
        max_dipole_am2: Vec3::new(10.0, 10.0, 10.0),
    };
    let w = Vec3::new(0.02, -0.05, 0.03);
    let b_inertial = Vec3::new(20_000.0, -15_000.0, 30_000.0);
    let dt = 0.1f32;
    let attitude = |t: f32| {
        let angle = w.norm() * t;
        let e = w.normalize();
        let (s, c) = (0.5 * angle).sin_cos();
        Quaternion {
            q0: c,
            q1: e.x * s,
            q2: e.y * s,
            q3: e.z * s,
        }
        .to_dcm()
    };
    let mut state = BdotState::default();
    let b0 = attitude(0.0).to_body(&b_inertial);
    assert_eq!(state.update(&config, &b0, dt).unwrap(), None);
    let b1 = attitude(dt).to_body(&b_inertial);
    let m_mag = state.update(&config, &b1, dt).unwrap().unwrap();
    let b_mid = attitude(0.5 * dt).to_body(&b_inertial);
    let m_gyro = bdot_from_rates(&config, &w, &b_mid).unwrap();
    assert!(
        (m_mag - m_gyro).norm() < 1e-3 * m_gyro.norm(),
        "{m_mag} vs {m_gyro}"
    );
    // a bad sample resets the state: the next good sample gives no output
    assert!(state
        .update(&config, &Vec3::new(f32::NAN, 0.0, 0.0), dt)
        .is_err());
    assert_eq!(state.update(&config, &b1, dt).unwrap(), None);
    assert!(state.update(&config, &b1, 0.0).is_err());
}

#[test]
fn dumping_torque_opposes_excess_momentum() {
    let h = Vec3::new(0.01, -0.004, 0.002);
    let b = Vec3::new(10_000.0, 25_000.0, -30_000.0);
    let m = dumping_dipole(&h, &Vec3::zeros(), 0.01, &b).unwrap();
    let tau = torque_of_dipole(&m, &b);
    // the external torque reduces the total momentum: τ·h < 0
    assert!(tau.dot(&h) < 0.0);
    assert!(dumping_dipole(&h, &Vec3::zeros(), -1.0, &b).is_err());
}

/// The attitude node's dumping to a zero target is bit-equal to `dumping_dipole` with a zero
/// target, and both to the law as first written, `B × (−k (h − 0)) / |B|²`'s torque
/// `(−(h − 0))·k` (signed zeros, a non-finite input and a gain that is not positive included).
#[test]
fn dumping_to_zero_is_bit_equal() {
    let mut rng = Rng(0x0dd_ba11);
    let bits = |r: Result<Vec3, MagnetorquerError>| r.map(|v| v.map(f32::to_bits));
    let zero = Vec3::zeros();
    let mut cases = Vec::new();
    for _ in 0..2000 {
        cases.push((rng.vec(0.05), rng.next() * 0.02, rng.vec(50_000.0)));
    }
    cases.push((
        Vec3::new(-0.0, 0.0, 0.01),
        0.01,
        Vec3::new(1.0e4, -2.0e4, 3.0e4),
    ));
    cases.push((
        Vec3::new(f32::NAN, 0.0, 0.01),
        0.01,
        Vec3::new(1.0e4, -2.0e4, 3.0e4),
    ));
    cases.push((
        Vec3::new(0.01, 0.0, 0.01),
        f32::INFINITY,
        Vec3::new(1.0e4, 2.0e4, 3.0e4),
    ));
    cases.push((
        Vec3::new(0.01, 0.0, 0.01),
        0.0,
        Vec3::new(1.0e4, 2.0e4, 3.0e4),
    ));
    cases.push((Vec3::new(0.01, 0.0, 0.01), 0.01, Vec3::zeros()));
    for (h, k, b) in cases {
        let new = bits(dumping_dipole_to_zero(&h, k, &b));
        assert_eq!(new, bits(dumping_dipole(&h, &zero, k, &b)), "{h:?} {k}");
        if k.is_finite() && k > 0.0 && h.iter().all(|x| x.is_finite()) {
            let first = dipole_for_torque(&(-(h - zero) * k), &b);
            assert_eq!(new, bits(first), "{h:?} {k}");
        }
    }
}

/// Rigid body with wheels, RK4 on (q, ω): I ω̇ = τ_ext − ω × (I ω + h) − ḣ, q̇ = ½ q ⊗ (0, ω).
fn simulate(
    inertia: &Mat3,
    q0: Quaternion,
    w0: Vec3,
    seconds: f32,
    dt: f32,
    mut torque: impl FnMut(&Quaternion, &Vec3) -> Vec3,
) -> (Quaternion, Vec3) {
    let inv = inertia.try_inverse().unwrap();
    let (mut q, mut w) = (q0, w0);
    let steps = (seconds / dt) as usize;
    for _ in 0..steps {
        // control held constant over the step (zero-order hold); wheels deliver it: ḣ = −τ
        let tau = torque(&q, &w);
        let deriv = |q: &Quaternion, w: &Vec3| {
            let wdot = inv * (tau - w.cross(&(inertia * w)));
            let qd = q.mul(&Quaternion {
                q0: 0.0,
                q1: w.x,
                q2: w.y,
                q3: w.z,
            });
            (
                Quaternion {
                    q0: 0.5 * qd.q0,
                    q1: 0.5 * qd.q1,
                    q2: 0.5 * qd.q2,
                    q3: 0.5 * qd.q3,
                },
                wdot,
            )
        };
        let add = |q: &Quaternion, d: &Quaternion, k: f32| Quaternion {
            q0: q.q0 + k * d.q0,
            q1: q.q1 + k * d.q1,
            q2: q.q2 + k * d.q2,
            q3: q.q3 + k * d.q3,
        };
        let (k1q, k1w) = deriv(&q, &w);
        let (k2q, k2w) = deriv(&add(&q, &k1q, 0.5 * dt), &(w + k1w * 0.5 * dt));
        let (k3q, k3w) = deriv(&add(&q, &k2q, 0.5 * dt), &(w + k2w * 0.5 * dt));
        let (k4q, k4w) = deriv(&add(&q, &k3q, dt), &(w + k3w * dt));
        let dq = Quaternion {
            q0: k1q.q0 + 2.0 * k2q.q0 + 2.0 * k3q.q0 + k4q.q0,
            q1: k1q.q1 + 2.0 * k2q.q1 + 2.0 * k3q.q1 + k4q.q1,
            q2: k1q.q2 + 2.0 * k2q.q2 + 2.0 * k3q.q2 + k4q.q2,
            q3: k1q.q3 + 2.0 * k2q.q3 + 2.0 * k3q.q3 + k4q.q3,
        };
        let qn = add(&q, &dq, dt / 6.0);
        q = Quaternion::new_normalize(qn.q0, qn.q1, qn.q2, qn.q3).unwrap();
        w += (k1w + k2w * 2.0 + k3w * 2.0 + k4w) * (dt / 6.0);
    }
    (q, w)
}

#[test]
fn tracking_converges_from_a_large_error_and_takes_the_short_way() {
    let inertia = Mat3::from_diagonal(&Vec3::new(0.042, 0.042, 0.0067));
    let gains = TrackingGains::from_bandwidth(&inertia, 0.1, 0.9);
    let target = Dcm::a3(0.4).then(&Dcm::a1(-0.2)).to_quaternion();
    // start 150° away about a skew axis, tumbling slowly
    let start = Dcm::a2(2.6)
        .then(&Dcm::a3(0.4))
        .then(&Dcm::a1(-0.2))
        .to_quaternion();
    let (q, w) = simulate(
        &inertia,
        start,
        Vec3::new(0.01, -0.02, 0.03),
        300.0,
        0.1,
        |q, w| {
            tracking_torque(
                &gains,
                &inertia,
                q,
                w,
                &target,
                &Vec3::zeros(),
                &Vec3::zeros(),
            )
            .unwrap()
        },
    );
    let e = attitude_error(&q, &target);
    // 2 asin |q_vec| resolves small angles (acos of q0 ≈ 1 cannot, in f32)
    let angle_deg = 2.0
        * Vec3::new(e.q1, e.q2, e.q3)
            .norm()
            .min(1.0)
            .asin()
            .to_degrees();
    figures::figure("control_laws.tracking_300s_deg", angle_deg);
    println!(
        "tracking after 300 s: error {angle_deg:.2e}°, |ω| {:.2e} rad/s",
        w.norm()
    );
    assert!(angle_deg < 0.01, "{angle_deg}");
    assert!(w.norm() < 1e-5);
    // sign: a small positive error about x gives a negative x torque
    let small = Quaternion::new_normalize(1.0, 0.01, 0.0, 0.0).unwrap();
    let t = tracking_torque(
        &gains,
        &inertia,
        &small,
        &Vec3::zeros(),
        &Quaternion::IDENTITY,
        &Vec3::zeros(),
        &Vec3::zeros(),
    )
    .unwrap();
    assert!(t.x < 0.0 && t.y == 0.0 && t.z == 0.0);
    // −q is the same attitude: same torque
    let neg = Quaternion {
        q0: -small.q0,
        q1: -small.q1,
        q2: -small.q2,
        q3: -small.q3,
    };
    let t2 = tracking_torque(
        &gains,
        &inertia,
        &neg,
        &Vec3::zeros(),
        &Quaternion::IDENTITY,
        &Vec3::zeros(),
        &Vec3::zeros(),
    )
    .unwrap();
    assert!((t - t2).norm() < 1e-9);
    let bad = Quaternion {
        q0: f32::NAN,
        ..small
    };
    assert!(tracking_torque(
        &gains,
        &inertia,
        &bad,
        &Vec3::zeros(),
        &Quaternion::IDENTITY,
        &Vec3::zeros(),
        &Vec3::zeros()
    )
    .is_err());
    // a negative gain on any axis, proportional or derivative, is refused
    for (k, v) in (0..6).map(|k| (k, -1e-9f32)) {
        let mut g = gains;
        if k < 3 {
            g.kp_nm[k] = v;
        } else {
            g.kd_nms[k - 3] = v;
        }
        assert_eq!(
            tracking_torque(
                &g,
                &inertia,
                &small,
                &Vec3::zeros(),
                &Quaternion::IDENTITY,
                &Vec3::zeros(),
                &Vec3::zeros()
            ),
            Err(acs::control::tracking::TrackingError::NegativeGain),
            "gain {k}"
        );
    }
}

/// Every one of the law's 32 inputs NaN, +∞ or −∞ (the others those of a tracking step in
/// progress, and of a satellite at rest on its target) gives `NotFinite`: the law checks its
/// result, not its inputs, and every input reaches the result.
#[test]
fn tracking_refuses_every_non_finite_input() {
    use acs::control::tracking::TrackingError;
    let inertia = Mat3::new(0.010, 1e-4, -2e-4, 1e-4, 0.012, 3e-4, -2e-4, 3e-4, 0.014);
    let gains = TrackingGains::from_bandwidth(&inertia, 0.5, 0.9);
    let q = Quaternion::new_normalize(0.9, 0.1, -0.2, 0.3).unwrap();
    let t = Quaternion::new_normalize(0.8, -0.1, 0.3, 0.2).unwrap();
    let cases = [
        (
            q,
            Vec3::new(1e-3, -2e-3, 5e-4),
            t,
            Vec3::new(2e-4, 1e-4, -3e-4),
            Vec3::new(1e-4, 2e-4, -1e-4),
        ),
        (
            Quaternion::IDENTITY,
            Vec3::zeros(),
            Quaternion::IDENTITY,
            Vec3::zeros(),
            Vec3::zeros(),
        ),
    ];
    for (q, w, t, wt, h) in cases {
        let base = [
            q.q0, q.q1, q.q2, q.q3, t.q0, t.q1, t.q2, t.q3, w.x, w.y, w.z, wt.x, wt.y, wt.z, h.x,
            h.y, h.z,
        ];
        let g = [gains.kp_nm, gains.kd_nms];
        for i in 0..32 {
            for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
                let mut x = base;
                let mut gg = g;
                let mut m = inertia;
                match i {
                    0..17 => x[i] = bad,
                    17..23 => gg[(i - 17) / 3][(i - 17) % 3] = bad,
                    _ => m[i - 23] = bad,
                }
                let quat = |k: usize| Quaternion {
                    q0: x[k],
                    q1: x[k + 1],
                    q2: x[k + 2],
                    q3: x[k + 3],
                };
                let v = |k: usize| Vec3::new(x[k], x[k + 1], x[k + 2]);
                let gains = TrackingGains {
                    kp_nm: gg[0],
                    kd_nms: gg[1],
                };
                let r = tracking_torque(&gains, &m, &quat(0), &v(8), &quat(4), &v(11), &v(14));
                assert_eq!(r, Err(TrackingError::NotFinite), "input {i} = {bad}");
            }
        }
    }
}

/// Every one of the sun-safe law's 11 inputs NaN, +∞ or −∞ (the others those of a step in
/// progress, of a satellite at rest on the Sun, with the Sun behind the axis, and in eclipse)
/// gives `NotFinite`: the law checks its result and its unit vectors, not each input.
#[test]
fn sun_safe_refuses_every_non_finite_input() {
    use acs::control::tracking::TrackingError;
    let gains = [2e-4f32, 4e-3];
    let axis = Vec3::new(0.0, 0.0, 1.0);
    let cases = [
        (
            Some(Vec3::new(0.3, -0.5, 0.81)),
            Vec3::new(1e-3, -2e-3, 5e-4),
        ),
        (Some(axis), Vec3::zeros()),
        (Some(-axis), Vec3::zeros()),
        (None, Vec3::new(1e-3, -2e-3, 5e-4)),
    ];
    for (sun, w) in cases {
        let s = sun.unwrap_or_else(Vec3::zeros);
        let base = [
            s.x, s.y, s.z, axis.x, axis.y, axis.z, w.x, w.y, w.z, gains[0], gains[1],
        ];
        // in eclipse the Sun is no input
        let first = if sun.is_some() { 0 } else { 3 };
        for i in first..base.len() {
            for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
                let mut x = base;
                x[i] = bad;
                let v = |k: usize| Vec3::new(x[k], x[k + 1], x[k + 2]);
                let g = SunSafeGains {
                    kp_nm: x[9],
                    kd_nms: x[10],
                };
                let sun = sun.map(|_| v(0));
                let r = sun_safe_torque(&g, sun.as_ref(), &v(3), &v(6));
                assert_eq!(
                    r,
                    Err(TrackingError::NotFinite),
                    "{sun:?}: input {i} = {bad}"
                );
            }
        }
    }
}

#[test]
fn sun_safe_points_the_axis_and_damps_in_eclipse() {
    let inertia = Mat3::from_diagonal(&Vec3::new(0.042, 0.042, 0.0067));
    let gains = SunSafeGains {
        kp_nm: 2e-4,
        kd_nms: 4e-3,
    };
    let sun_ref = Vec3::new(0.3, -0.5, 0.8).normalize();
    let axis = Vec3::z();
    // start with the Sun almost exactly behind the panel (anti-aligned)
    let start = Dcm::a1(std::f32::consts::PI - 0.001).to_quaternion();
    let sun_in_start = start.to_dcm().to_body(&sun_ref);
    let to_behind = {
        // rotate the body so that the Sun is at −z to start
        let c = sun_in_start.cross(&-axis);
        let s = c.norm();
        let angle = s.atan2(sun_in_start.dot(&-axis));
        let e = c / s;
        let (sh, ch) = (0.5 * angle).sin_cos();
        Quaternion {
            q0: ch,
            q1: e.x * sh,
            q2: e.y * sh,
            q3: e.z * sh,
        }
    };
    let q_start = start.mul(&to_behind);
    let (q, w) = simulate(&inertia, q_start, Vec3::zeros(), 600.0, 0.1, |q, w| {
        let s = q.to_dcm().to_body(&sun_ref);
        sun_safe_torque(&gains, Some(&s), &axis, w).unwrap()
    });
    let s = q.to_dcm().to_body(&sun_ref);
    let err_deg = s.cross(&axis).norm().atan2(s.dot(&axis)).to_degrees();
    figures::figure("control_laws.sun_safe_600s_deg", err_deg);
    println!(
        "sun-safe after 600 s: pointing error {err_deg:.3e}°, |ω| {:.2e}",
        w.norm()
    );
    assert!(err_deg < 0.1, "{err_deg}");
    // eclipse: pure damping, opposite to the rate
    let w = Vec3::new(0.1, 0.0, -0.2);
    let t = sun_safe_torque(&gains, None, &axis, &w).unwrap();
    assert!((t + w * gains.kd_nms).norm() < 1e-9);
    assert!(sun_safe_torque(&gains, Some(&Vec3::new(f32::NAN, 0.0, 1.0)), &axis, &w).is_err());
    assert!(sun_safe_torque(&gains, Some(&Vec3::zeros()), &axis, &w).is_err());
}

/// The sun-safe law's damping, `ω·(−K_d)`, is bit-equal to the law as first written,
/// `(−ω)·K_d`: in the eclipse (damping only) and with the Sun (`cross·K_p + damping`).
#[test]
fn sun_safe_damping_is_bit_equal() {
    let mut rng = Rng(0x5afe_5afe);
    let axis = Vec3::new(0.0, 0.0, 1.0);
    for i in 0..2000 {
        let gains = SunSafeGains {
            kp_nm: rng.next().abs() * 1e-3,
            kd_nms: rng.next().abs() * 1e-2,
        };
        let mut w = rng.vec(0.1);
        if i % 7 == 0 {
            w.x = if i % 2 == 0 { 0.0 } else { -0.0 };
        }
        let s = rng.vec(1.0);
        let first_damping = -w * gains.kd_nms;
        let eclipse = sun_safe_torque(&gains, None, &axis, &w).unwrap();
        assert_eq!(eclipse.map(f32::to_bits), first_damping.map(f32::to_bits));
        if let Some(su) = s.try_normalize(0.0) {
            if axis.dot(&su) >= -0.998 {
                let first = axis.cross(&su) * gains.kp_nm + first_damping * 1.0;
                let lit = sun_safe_torque(&gains, Some(&s), &axis, &w).unwrap();
                assert_eq!(
                    lit.map(f32::to_bits),
                    first.map(f32::to_bits),
                    "{w:?} {s:?}"
                );
            }
        }
    }
}

/// B-dot's derivative form, `Ḃ·(−k)`, is bit-equal to the law as first written, `(−Ḃ)·k`,
/// saturated the same way.
#[test]
fn bdot_derivative_is_bit_equal() {
    let mut rng = Rng(0xb_d07);
    let config = BdotConfig {
        gain: 3e4,
        max_dipole_am2: Vec3::new(0.2, 0.2, 0.2),
    };
    for i in 0..2000 {
        let (b0, b1) = (rng.vec(40_000.0), rng.vec(40_000.0));
        let b1 = if i % 5 == 0 {
            Vec3::new(b0.x, b1.y, b1.z)
        } else {
            b1
        };
        let dt = 0.1 + rng.next().abs();
        let mut state = BdotState::default();
        assert_eq!(state.update(&config, &b0, dt), Ok(None));
        let m = state.update(&config, &b1, dt).unwrap().unwrap();
        let first = -((b1 - b0) * (1e-9 / dt)) * config.gain;
        let (first, _) = saturate_dipole(&first, &config.max_dipole_am2).unwrap();
        assert_eq!(
            m.map(f32::to_bits),
            first.map(f32::to_bits),
            "{b0:?} {b1:?}"
        );
    }
}
