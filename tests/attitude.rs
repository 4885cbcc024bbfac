//! Attitude conventions (`acs::attitude`): the thesis's test matrices and Euler angles
//! (note 000 §3.7, §4.2, §4.8, §1.2), round trips and properties.
//!
//! Run with `cargo test --test attitude -- --nocapture` to print the measured errors.

// The thesis's numbers are kept verbatim (15 digits), even where f32 cannot hold them.
#![allow(clippy::excessive_precision, clippy::approx_constant)]

use acs::attitude::{Dcm, Euler313, Euler321, Quaternion};
use acs::linalg::{Mat3, Vec3};

mod figures;
use figures::figure;

const DEG: f32 = core::f32::consts::PI / 180.0;

fn max_abs(a: &Mat3, b: &Mat3) -> f32 {
    (a - b).amax()
}

fn assert_mat_close(actual: &Mat3, expected: &Mat3, tol: f32, what: &str) {
    let e = max_abs(actual, expected);
    assert!(
        e <= tol,
        "{what}: max |Δ| = {e:e} > {tol:e}\nactual {actual}\nexpected {expected}"
    );
}

fn assert_close(actual: f32, expected: f32, tol: f32, what: &str) {
    assert!(
        (actual - expected).abs() <= tol,
        "{what}: {actual} vs {expected} (|Δ| = {:e} > {tol:e})",
        (actual - expected).abs()
    );
}

/// Small deterministic generator (xorshift64*), so the property tests need no extra crate.
struct Rng(u64);
impl Rng {
    fn next_f64(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn uniform(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.next_f64() as f32
    }
    fn quaternion(&mut self) -> Quaternion {
        loop {
            let q = [
                self.uniform(-1.0, 1.0),
                self.uniform(-1.0, 1.0),
                self.uniform(-1.0, 1.0),
                self.uniform(-1.0, 1.0),
            ];
            let n2: f32 = q.iter().map(|x| x * x).sum();
            if n2 > 0.01 && n2 <= 1.0 {
                return Quaternion::new_normalize(q[0], q[1], q[2], q[3]).unwrap();
            }
        }
    }
}

/// Note 000 §4.2: the true attitude of the chapter-12 tests, 3-2-1 Euler angles
/// Φ = 0°, θ = −30°, Ψ = −45°.
fn thesis_a() -> Mat3 {
    Mat3::new(
        0.612372435695794,
        -0.612372435695795,
        0.500000000000000,
        0.707106781186548,
        0.707106781186547,
        0.0,
        -0.353553390593274,
        0.353553390593274,
        0.866025403784439,
    )
}

#[test]
fn thesis_true_attitude_from_euler_321() {
    let e = Euler321 {
        phi_rad: 0.0,
        theta_rad: -30.0 * DEG,
        psi_rad: -45.0 * DEG,
    };
    let a = Dcm::from_euler_321(&e);
    figure("attitude.thesis_a", max_abs(a.matrix(), &thesis_a()));
    assert_mat_close(a.matrix(), &thesis_a(), 2e-7, "A(0, −30°, −45°)");
    let back = Dcm::from_matrix_unchecked(thesis_a()).to_euler_321();
    println!(
        "A → 3-2-1: Φ = {:e}°, θ = {}°, Ψ = {}°",
        back.phi_rad / DEG,
        back.theta_rad / DEG,
        back.psi_rad / DEG
    );
    assert_close(back.phi_rad, 0.0, 1e-7, "Φ");
    assert_close(back.theta_rad, -30.0 * DEG, 2e-7, "θ");
    assert_close(back.psi_rad, -45.0 * DEG, 2e-7, "Ψ");
}

#[test]
fn thesis_desired_attitude() {
    // Note 000 §4.2: A_d = [[1,0,0],[0,0,1],[0,−1,0]], 90° about I (Φ = 90°, θ = Ψ = 0).
    let ad = Mat3::new(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0);
    let a = Dcm::from_euler_321(&Euler321 {
        phi_rad: 90.0 * DEG,
        theta_rad: 0.0,
        psi_rad: 0.0,
    });
    assert_mat_close(a.matrix(), &ad, 1e-7, "A_d");
    let aa = Dcm::from_matrix_unchecked(ad).to_axis_angle();
    assert_close(aa.angle_rad, 90.0 * DEG, 1e-7, "A_d angle");
    assert!((aa.axis - Vec3::x()).norm() < 1e-7);
    let q = Dcm::from_matrix_unchecked(ad).to_quaternion();
    let h = core::f32::consts::FRAC_1_SQRT_2;
    assert_close(q.q0, h, 1e-7, "q0");
    assert_close(q.q1, h, 1e-7, "q1");
    assert_close(q.q2, 0.0, 1e-7, "q2");
    assert_close(q.q3, 0.0, 1e-7, "q3");
}

#[test]
fn chapter_10_factorisation_matrix() {
    // Note 000 §4.8: A1(Φ)·A2(θ)·A3(Ψ) with Ψ = 4.3813913795535°, θ = −4.0647534189236°,
    // Φ = 89.688448985754° equals M_abc (printed to 15 digits).
    let m_abc = Mat3::new(
        0.994569544805816,
        0.076203033375386,
        0.070883836303769,
        -0.071091045497045,
        0.000006568776463,
        0.997469830725215,
        0.076009761181619,
        -0.997092321533589,
        0.005423886417720,
    );
    let e = Euler321 {
        phi_rad: (89.688448985754f64.to_radians()) as f32,
        theta_rad: ((-4.0647534189236f64).to_radians()) as f32,
        psi_rad: (4.3813913795535f64.to_radians()) as f32,
    };
    let a = Dcm::from_euler_321(&e);
    let err = max_abs(a.matrix(), &m_abc);
    figure("attitude.chapter_10", err);
    println!("chapter 10: max |A1A2A3 − M_abc| = {err:e}");
    assert!(err <= 3e-7, "{err:e}");
    let back = Dcm::from_matrix_unchecked(m_abc).to_euler_321();
    println!(
        "chapter 10: angles back {:.10}° {:.10}° {:.10}°",
        back.phi_rad / DEG,
        back.theta_rad / DEG,
        back.psi_rad / DEG
    );
    assert_close(back.phi_rad, e.phi_rad, 4e-7, "Φ");
    assert_close(back.theta_rad, e.theta_rad, 4e-7, "θ");
    assert_close(back.psi_rad, e.psi_rad, 4e-7, "Ψ");
}

/// Note 000 §1.2: the six tile matrices of the chapter-12 cube, with the axis and angle each
/// is (checked by hand: A0 = A2(90°), A5 = A2(180°), A3 = 180° about (1, 0, −1)/√2, …). These
/// exercise all four pivots of the DCM → quaternion conversion.
#[test]
fn tile_matrices_axis_angle_and_pivots() {
    let tiles = [
        Mat3::new(0.0, 0.0, -1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0),
        Mat3::new(0.0, 0.0, -1.0, -1.0, 0.0, 0.0, 0.0, 1.0, 0.0),
        Mat3::identity(),
        Mat3::new(0.0, 0.0, -1.0, 0.0, -1.0, 0.0, -1.0, 0.0, 0.0),
        Mat3::new(0.0, 0.0, -1.0, 1.0, 0.0, 0.0, 0.0, -1.0, 0.0),
        Mat3::new(-1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1.0),
    ];
    let s2 = core::f32::consts::FRAC_1_SQRT_2;
    let expected_angle_deg = [90.0, 120.0, 0.0, 180.0, 120.0, 180.0];
    for (m, (tile, angle)) in tiles.iter().zip(expected_angle_deg.iter()).enumerate() {
        let a = Dcm::from_matrix_unchecked(*tile);
        assert_close(a.determinant(), 1.0, 0.0, "det");
        let q = a.to_quaternion();
        assert_close(q.norm(), 1.0, 1e-7, "|q|");
        assert!(q.q0 >= 0.0);
        assert_mat_close(q.to_dcm().matrix(), tile, 2e-7, &format!("A{m} round trip"));
        let aa = a.to_axis_angle();
        assert_close(aa.angle_rad, angle * DEG, 2e-7, &format!("A{m} angle"));
        let rebuilt = Dcm::from_axis_angle(&aa.axis, aa.angle_rad).unwrap();
        assert_mat_close(rebuilt.matrix(), tile, 3e-7, &format!("A{m} axis-angle"));
    }
    // A0 is 90° about +V, A5 180° about V, A3 180° about (1, 0, −1)/√2 (either sign).
    let a0 = Dcm::from_matrix_unchecked(tiles[0]).to_axis_angle();
    assert!((a0.axis - Vec3::y()).norm() < 1e-7);
    let a3 = Dcm::from_matrix_unchecked(tiles[3]).to_axis_angle();
    assert!((a3.axis.abs() - Vec3::new(s2, 0.0, s2)).norm() < 2e-7);
    assert!(a3.axis.x * a3.axis.z < 0.0);
    assert_mat_close(Dcm::a2(90.0 * DEG).matrix(), &tiles[0], 1e-7, "A2(90°)");
}

#[test]
fn axis_angle_formula_eq_5_13() {
    // A = cosΦ·I + (1 − cosΦ)·e·eᵀ − sinΦ·[e×] (eq. 5.12) against the quaternion route.
    let mut rng = Rng(7);
    let mut worst = 0.0f32;
    for _ in 0..2000 {
        let e = Vec3::new(
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
        );
        if e.norm() < 0.1 {
            continue;
        }
        let e = e.normalize();
        let phi = rng.uniform(-3.2, 3.2);
        let (s, c) = (phi.sin(), phi.cos());
        let skew = Mat3::new(0.0, -e.z, e.y, e.z, 0.0, -e.x, -e.y, e.x, 0.0);
        let expected = Mat3::identity() * c + e * e.transpose() * (1.0 - c) - skew * s;
        let a = Dcm::from_axis_angle(&e, phi).unwrap();
        worst = worst.max(max_abs(a.matrix(), &expected));
    }
    println!("axis-angle: max |A(q(e,Φ)) − eq. 5.12| = {worst:e}");
    assert!(worst < 5e-7, "{worst:e}");
    assert!(Dcm::from_axis_angle(&Vec3::zeros(), 1.0).is_err());
    assert!(Dcm::from_axis_angle(&Vec3::x(), f32::NAN).is_err());
}

#[test]
fn quaternion_properties() {
    let mut rng = Rng(12345);
    let (mut worst_compose, mut worst_norm, mut worst_rt, mut worst_q) = (0f32, 0f32, 0f32, 0f32);
    let (mut worst_321, mut worst_313, mut worst_aa) = (0f32, 0f32, 0f32);
    for i in 0..20_000 {
        let mut p = rng.quaternion();
        let r = rng.quaternion();
        if i % 4 == 0 {
            // Near 180°: q0 tiny, so the q0 pivot would divide by ~0.
            p.q0 *= 1e-4;
            p = Quaternion::new_normalize(p.q0, p.q1, p.q2, p.q3).unwrap();
        }
        // A(p ⊗ r) = A(r)·A(p) (note 000 §3.7).
        let lhs = p.mul(&r).to_dcm();
        let rhs = p.to_dcm().then(&r.to_dcm());
        worst_compose = worst_compose.max(max_abs(lhs.matrix(), rhs.matrix()));
        assert_mat_close(
            rhs.matrix(),
            &(r.to_dcm().matrix() * p.to_dcm().matrix()),
            0.0,
            "then",
        );
        // The product preserves the norm.
        worst_norm = worst_norm.max((p.mul(&r).norm() - 1.0).abs());
        // q and −q give the same DCM.
        let neg = Quaternion {
            q0: -p.q0,
            q1: -p.q1,
            q2: -p.q2,
            q3: -p.q3,
        };
        assert_eq!(neg.to_dcm(), p.to_dcm());
        // DCM → quaternion → DCM and quaternion → DCM → quaternion.
        let a = p.to_dcm();
        let q = a.to_quaternion();
        worst_rt = worst_rt.max(max_abs(q.to_dcm().matrix(), a.matrix()));
        let pc = p.canonical();
        let dq = [q.q0 - pc.q0, q.q1 - pc.q1, q.q2 - pc.q2, q.q3 - pc.q3];
        let dq_alt = [q.q0 + pc.q0, q.q1 + pc.q1, q.q2 + pc.q2, q.q3 + pc.q3];
        let e1 = dq.iter().fold(0f32, |m, x| m.max(x.abs()));
        let e2 = dq_alt.iter().fold(0f32, |m, x| m.max(x.abs()));
        worst_q = worst_q.max(e1.min(e2));
        // Euler 3-2-1 and 3-1-3 round trips through the matrix.
        let a321 = Dcm::from_euler_321(&a.to_euler_321());
        worst_321 = worst_321.max(max_abs(a321.matrix(), a.matrix()));
        let a313 = Dcm::from_euler_313(&a.to_euler_313());
        worst_313 = worst_313.max(max_abs(a313.matrix(), a.matrix()));
        let aa = a.to_axis_angle();
        assert!((0.0..=core::f32::consts::PI).contains(&aa.angle_rad));
        let a_aa = Dcm::from_axis_angle(&aa.axis, aa.angle_rad).unwrap();
        worst_aa = worst_aa.max(max_abs(a_aa.matrix(), a.matrix()));
    }
    figure("attitude.compose", worst_compose);
    figure("attitude.compose_norm", worst_norm);
    figure("attitude.q_a_q", worst_q);
    figure("attitude.a_q_a", worst_rt);
    figure(
        "attitude.euler_axis_angle",
        worst_321.max(worst_313).max(worst_aa),
    );
    println!("A(p⊗r) vs A(r)A(p): max |Δ| = {worst_compose:e}");
    println!("| |p⊗r| − 1 |: max {worst_norm:e}");
    println!("q → A → q: max |Δq| = {worst_q:e}; A → q → A: max |ΔA| = {worst_rt:e}");
    println!("A → 3-2-1 → A: {worst_321:e}; A → 3-1-3 → A: {worst_313:e}; A → axis-angle → A: {worst_aa:e}");
    assert!(worst_compose < 5e-7);
    assert!(worst_norm < 5e-7);
    assert!(worst_q < 3e-7, "{worst_q:e}");
    // f32: 5 ulp of 1 (the products of four rounded components).
    assert!(worst_rt < 6e-7, "{worst_rt:e}");
    assert!(worst_321 < 1e-6, "{worst_321:e}");
    assert!(worst_313 < 1e-6, "{worst_313:e}");
    assert!(worst_aa < 5e-7, "{worst_aa:e}");
}

#[test]
fn euler_gimbal_lock_rebuilds_the_matrix() {
    for theta in [90.0f32, -90.0] {
        for (phi, psi) in [(10.0f32, 20.0f32), (0.0, 0.0), (-170.0, 45.0)] {
            let e = Euler321 {
                phi_rad: phi * DEG,
                theta_rad: theta * DEG,
                psi_rad: psi * DEG,
            };
            let a = Dcm::from_euler_321(&e);
            let b = Dcm::from_euler_321(&a.to_euler_321());
            assert_mat_close(b.matrix(), a.matrix(), 1e-6, "3-2-1 at θ = ±90°");
        }
    }
    for theta in [0.0f32, 180.0] {
        let e = Euler313 {
            phi_rad: 30.0 * DEG,
            theta_rad: theta * DEG,
            psi_rad: -60.0 * DEG,
        };
        let a = Dcm::from_euler_313(&e);
        let b = Dcm::from_euler_313(&a.to_euler_313());
        assert_mat_close(b.matrix(), a.matrix(), 1e-6, "3-1-3 at θ = 0, π");
    }
    // 3-1-3 eq. 5.28 on a regular case.
    let e = Euler313 {
        phi_rad: 30.0 * DEG,
        theta_rad: 50.0 * DEG,
        psi_rad: -120.0 * DEG,
    };
    let back = Dcm::from_euler_313(&e).to_euler_313();
    assert_close(back.phi_rad, e.phi_rad, 3e-7, "Φ");
    assert_close(back.theta_rad, e.theta_rad, 3e-7, "θ");
    assert_close(back.psi_rad, e.psi_rad, 3e-7, "Ψ");
}

#[test]
fn rotation_angle_between_attitudes() {
    let mut rng = Rng(99);
    let (mut worst, mut worst_q, mut worst_ba) = (0f32, 0f32, 0f32);
    for _ in 0..2000 {
        let p = rng.quaternion();
        let axis = Vec3::new(
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
        );
        let angle = if rng.next_f64() < 0.5 {
            rng.uniform(0.0, 1e-3)
        } else {
            rng.uniform(0.0, 3.14159)
        };
        let d = Quaternion::from_axis_angle(&axis, angle).unwrap();
        let q = p.mul(&d);
        let a = p.to_dcm();
        let b = q.to_dcm();
        let e = (a.angle_to(&b) - angle).abs();
        worst = worst.max(e);
        worst_q = worst_q.max((p.angle_to(&q) - angle).abs());
        worst_ba = worst_ba.max((b.angle_to(&a) - angle).abs());
    }
    figure(
        "attitude.angle_between_rad",
        worst.max(worst_ba).max(worst_q),
    );
    println!("angle between attitudes: max |Δ| = {worst:e} rad (DCM), {worst_ba:e} (reversed), {worst_q:e} (quaternion)");
    // f32: a few ulp of π (ulp 2.4e-7) from rounding the inputs and the product.
    assert!(worst < 1e-6, "{worst:e}");
    assert!(worst_ba < 1e-6, "{worst_ba:e}");
    assert!(worst_q < 1e-6, "{worst_q:e}");
}

#[test]
fn orthonormalize_near_rotation() {
    let mut rng = Rng(2024);
    let mut worst_eo = 0f32;
    for i in 0..2000 {
        let q = rng.quaternion();
        let a = q.to_dcm();
        // A symmetric perturbation of a rotation A·(I + S) has the orthogonal polar factor A.
        let s = 1e-2 * if i % 2 == 0 { 1.0 } else { 0.01 };
        let mut sym = Mat3::from_fn(|_, _| rng.uniform(-s, s));
        sym = (sym + sym.transpose()) * 0.5;
        let m = a.matrix() * (Mat3::identity() + sym);
        let r = Dcm::orthonormalize(&m).unwrap();
        assert!((r.determinant() - 1.0).abs() < 1e-6);
        assert!(r.orthogonality_error() < 1e-6);
        worst_eo = worst_eo.max(r.angle_to(&a));
    }
    figure("attitude.orthonormalize_rad", worst_eo);
    println!("orthonormalize: max angle from the polar factor = {worst_eo:e} rad");
    assert!(worst_eo < 1e-6);
    // The thesis's Test 2 A_eo (note 000 §4.4) is 0.35° from the identity.
    let aeo = Mat3::new(
        1.002426189268299,
        -0.004349217591536,
        -0.001451863972351,
        0.004548433785015,
        1.000232001286781,
        -0.005993505252486,
        0.007938882085486,
        -0.003566929936326,
        0.995575797410828,
    );
    let r = Dcm::orthonormalize(&aeo).unwrap();
    println!(
        "orthonormalize(A_eo of Test 2): |AAᵀ − I| = {:e}",
        r.orthogonality_error()
    );
    assert!(r.orthogonality_error() < 1e-6);
    // A reflection gets its smallest singular direction flipped: a proper rotation comes back.
    let refl = Mat3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1.0);
    assert!((Dcm::orthonormalize(&refl).unwrap().determinant() - 1.0).abs() < 1e-6);
    assert!(Dcm::orthonormalize(&Mat3::zeros()).is_err());
    assert!(Dcm::orthonormalize(&(Vec3::x() * Vec3::y().transpose())).is_err());
    assert!(Dcm::orthonormalize(&Mat3::from_element(f32::NAN)).is_err());
}
