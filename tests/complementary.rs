//! The loop's complementary attitude filter (`acs::determination::complementary`): the f32
//! prediction against the same first-order scheme in f64 (rounding) and against the exact
//! rotation (truncation), the correction, the ageing and bad input.
//! `cargo test --test complementary -- --nocapture` prints the measured errors.

use acs::attitude::Quaternion;
use acs::determination::complementary::{update, Estimate, FilterConfig};
use acs::linalg::Vec3;

/// Rotation angle (rad) between two attitudes, in f64: `2·atan2(|δ_v|, |δ₀|)` of `δ = a* ⊗ b`
/// (well conditioned for small angles, unlike `acos` of the dot product).
fn angle_between(a: [f64; 4], b: [f64; 4]) -> f64 {
    let d = mul64([a[0], -a[1], -a[2], -a[3]], b);
    let v = (d[1] * d[1] + d[2] * d[2] + d[3] * d[3]).sqrt();
    2.0 * v.atan2(d[0].abs())
}

fn q64(q: &Quaternion) -> [f64; 4] {
    [q.q0 as f64, q.q1 as f64, q.q2 as f64, q.q3 as f64]
}

/// Hamilton product `p ⊗ r` in f64, the convention of `Quaternion::mul`.
fn mul64(p: [f64; 4], r: [f64; 4]) -> [f64; 4] {
    [
        p[0] * r[0] - p[1] * r[1] - p[2] * r[2] - p[3] * r[3],
        p[1] * r[0] + p[2] * r[3] - p[3] * r[2] + p[0] * r[1],
        -p[1] * r[3] + p[2] * r[0] + p[3] * r[1] + p[0] * r[2],
        p[1] * r[2] - p[2] * r[1] + p[3] * r[0] + p[0] * r[3],
    ]
}

fn normalised(q: [f64; 4]) -> [f64; 4] {
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    [q[0] / n, q[1] / n, q[2] / n, q[3] / n]
}

const CONFIG: FilterConfig = FilterConfig {
    gain: 0.1,
    max_propagation_s: 120.0,
};

#[test]
fn prediction_against_f64_and_exact_rotation() {
    let start = Quaternion::new_normalize(0.9, -0.2, 0.3, 0.25).unwrap();
    let omega = [0.011_f32, -0.023, 0.017];
    let w = Vec3::new(omega[0], omega[1], omega[2]);
    let dt = 1.0_f32;
    let steps = 100;
    let mut e = Some(Estimate {
        attitude: start,
        age_s: 0.0,
    });
    let mut same_scheme = q64(&start);
    let (mut worst_rounding, mut worst_truncation) = (0.0f64, 0.0f64);
    let rate = omega
        .iter()
        .map(|x| (*x as f64).powi(2))
        .sum::<f64>()
        .sqrt();
    let axis = omega.map(|x| x as f64 / rate);
    for k in 1..=steps {
        e = update(
            &FilterConfig {
                gain: 0.1,
                max_propagation_s: 1e6,
            },
            e,
            None,
            Some(w),
            dt,
        );
        let got = q64(&e.unwrap().attitude);
        let h = 0.5 * dt as f64;
        let dq = [
            1.0,
            omega[0] as f64 * h,
            omega[1] as f64 * h,
            omega[2] as f64 * h,
        ];
        same_scheme = normalised(mul64(same_scheme, dq));
        let half = 0.5 * rate * dt as f64 * k as f64;
        let exact = mul64(
            q64(&start),
            [
                half.cos(),
                axis[0] * half.sin(),
                axis[1] * half.sin(),
                axis[2] * half.sin(),
            ],
        );
        worst_rounding = worst_rounding.max(angle_between(got, same_scheme));
        worst_truncation = worst_truncation.max(angle_between(same_scheme, exact));
    }
    // first order: each step turns by 2·atan(|ω|Δt/2) instead of |ω|Δt, (|ω|Δt)³/12 short
    let truncation_bound = steps as f64 * (rate * dt as f64).powi(3) / 12.0;
    println!(
        "prediction over {steps} s at {rate:.4} rad/s: f32 vs f64 same scheme {worst_rounding:.3e} rad, \
         scheme vs exact rotation {worst_truncation:.3e} rad (bound {truncation_bound:.3e})"
    );
    assert!(worst_rounding < 2e-6, "rounding {worst_rounding:e}");
    assert!(
        worst_truncation <= truncation_bound * 1.001,
        "truncation {worst_truncation:e}"
    );
    assert_eq!(e.unwrap().age_s, steps as f32 * dt);
}

#[test]
fn correction_turns_by_the_gain_fraction_of_the_vector_part() {
    let p = Quaternion::new_normalize(0.95, 0.1, -0.2, 0.2).unwrap();
    let m = Quaternion::new_normalize(0.9, 0.15, -0.25, 0.3).unwrap();
    let apart = angle_between(q64(&p), q64(&m));
    let zero = Some(Vec3::zeros());
    let before = Some(Estimate {
        attitude: p,
        age_s: 3.0,
    });
    let one = update(
        &FilterConfig {
            gain: 1.0,
            max_propagation_s: 120.0,
        },
        before,
        Some(m),
        zero,
        1.0,
    )
    .unwrap();
    let part = update(&CONFIG, before, Some(m), zero, 1.0).unwrap();
    // the correction (1, k·δ_v) turns towards the measurement by 2·atan(k·sin(θ/2)): about k·θ
    // for small θ, and short of θ for k = 1 by θ − 2·atan(sin(θ/2)) ≈ θ³/8 (0.0024 rad here)
    let mut worst = 0.0f64;
    for (k, e) in [(1.0, one), (0.1, part)] {
        let moved = angle_between(q64(&p), q64(&e.attitude));
        let left = angle_between(q64(&e.attitude), q64(&m));
        let expected = 2.0 * (k * (apart / 2.0).sin()).atan();
        println!(
            "correction, gain {k}: moved {moved:.6} rad of {apart:.6} (model {expected:.6}), \
             {left:.3e} rad left"
        );
        worst = worst
            .max((moved - expected).abs())
            .max((moved + left - apart).abs());
    }
    println!("correction: worst difference from the model {worst:.3e} rad");
    assert!(worst < 1e-6, "{worst:e}");
    assert_eq!(part.age_s, 0.0);
    // the measurement's sign does not matter (q and −q are the same attitude)
    let neg = Quaternion {
        q0: -m.q0,
        q1: -m.q1,
        q2: -m.q2,
        q3: -m.q3,
    };
    let part_neg = update(&CONFIG, before, Some(neg), zero, 1.0).unwrap();
    assert!(angle_between(q64(&part.attitude), q64(&part_neg.attitude)) < 1e-6);
}

#[test]
fn ageing_and_restart() {
    let q = Quaternion::new_normalize(1.0, 0.0, 0.0, 0.0).unwrap();
    let w = Some(Vec3::new(0.0, 0.0, 0.001));
    // a measurement alone starts the estimate
    let mut e = update(&CONFIG, None, Some(q), None, 1.0);
    assert_eq!(e.map(|e| e.age_s), Some(0.0));
    // kept without measurements for at most max_propagation_s
    for _ in 0..120 {
        e = update(&CONFIG, e, None, w, 1.0);
        assert!(e.is_some());
    }
    assert_eq!(e.map(|e| e.age_s), Some(120.0));
    assert_eq!(update(&CONFIG, e, None, w, 1.0), None);
    // without a rate there is no prediction: the estimate is dropped, a measurement restarts it
    assert_eq!(update(&CONFIG, e, None, None, 1.0), None);
    assert_eq!(
        update(&CONFIG, e, Some(q), None, 1.0).map(|e| e.age_s),
        Some(0.0)
    );
}

#[test]
fn bad_input_gives_no_estimate_and_never_panics() {
    let q = Quaternion::new_normalize(0.8, 0.2, 0.4, 0.4).unwrap();
    let e = Some(Estimate {
        attitude: q,
        age_s: 0.0,
    });
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let w = Some(Vec3::new(bad, 0.0, 0.0));
        assert_eq!(update(&CONFIG, e, None, w, 1.0), None);
        assert_eq!(update(&CONFIG, e, None, Some(Vec3::zeros()), bad), None);
        // a measurement still restarts the estimate when the prediction failed
        assert_eq!(
            update(&CONFIG, e, Some(q), w, 1.0).map(|e| e.attitude),
            Some(q)
        );
        let m_bad = Quaternion {
            q0: bad,
            q1: 0.0,
            q2: 0.0,
            q3: 0.0,
        };
        assert_eq!(
            update(&CONFIG, e, Some(m_bad), Some(Vec3::zeros()), 1.0),
            None
        );
    }
}
