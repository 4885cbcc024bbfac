//! Accuracy of the f32 kernels of `acs::fmath` against the host's f64 functions.
//!
//! Dense tests (default): every f32 bit pattern of the domain in a fixed stride, plus special
//! values. Exhaustive tests (every f32 of the domain; `#[ignore]`, a few minutes in release):
//! `cargo test --release --test fmath -- --ignored --nocapture`.
//! The measured maxima are printed (`--nocapture`) and are the figures of `src/fmath.rs`'s docs.

use acs::fmath;

/// One ulp of the f32 nearest to `want` (the spacing of f32 at that magnitude; subnormal spacing
/// below the normal range).
fn ulp_of(want: f64) -> f64 {
    let a = want.abs();
    if a < f64::from(f32::MIN_POSITIVE) {
        return 2f64.powi(-149);
    }
    let e = a.log2().floor() as i32;
    2f64.powi(e - 23)
}

/// Error of `got` against the f64 reference `want`, in ulp of the result.
fn ulp_err(got: f32, want: f64) -> f64 {
    (f64::from(got) - want).abs() / ulp_of(want)
}

/// Every f32 with bit pattern in `lo..=hi` (positive numbers), in steps of `stride`, both signs.
fn floats(lo: u32, hi: u32, stride: u32) -> impl Iterator<Item = f32> {
    (lo..=hi)
        .step_by(stride as usize)
        .flat_map(|b| [f32::from_bits(b), -f32::from_bits(b)])
}

/// Max ulp error of `f` against `reference` over every f32 with |x| in `0..=hi` in `stride`.
fn max_ulp(
    hi: f32,
    stride: u32,
    f: impl Fn(f32) -> f32,
    reference: impl Fn(f64) -> f64,
) -> (f64, f32) {
    let mut worst = (0.0, 0.0);
    for x in floats(0, hi.to_bits(), stride) {
        let e = ulp_err(f(x), reference(f64::from(x)));
        if e > worst.0 {
            worst = (e, x);
        }
    }
    worst
}

/// A small deterministic generator (no dependency): xorshift32.
struct Rng(u32);
impl Rng {
    fn next(&mut self) -> u32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 17;
        self.0 ^= self.0 << 5;
        self.0
    }
    /// Uniform in [-1, 1).
    fn unit(&mut self) -> f64 {
        f64::from(self.next()) / 2f64.powi(31) - 1.0
    }
}

const STRIDE: u32 = 997;

#[test]
fn sin_cos_reduced_range_within_1_ulp() {
    let (es, xs) = max_ulp(std::f32::consts::FRAC_PI_4, STRIDE, fmath::sin, f64::sin);
    let (ec, xc) = max_ulp(std::f32::consts::FRAC_PI_4, STRIDE, fmath::cos, f64::cos);
    println!("|x| <= pi/4: sin max {es:.3} ulp (x = {xs:e}), cos max {ec:.3} ulp (x = {xc:e})");
    assert!(es <= 1.0 && ec <= 1.0);
}

/// Absolute error of sin and cos over |x| <= `hi`, `n` uniform samples.
fn trig_abs_error(hi: f64, n: usize, seed: u32) -> (f64, f64) {
    let mut rng = Rng(seed);
    let (mut worst, mut sum2) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let x = (rng.unit() * hi) as f32;
        let xd = f64::from(x);
        let (s, c) = fmath::sincos(x);
        assert_eq!(
            (s.to_bits(), c.to_bits()),
            (fmath::sin(x).to_bits(), fmath::cos(x).to_bits())
        );
        for e in [
            (f64::from(s) - xd.sin()).abs(),
            (f64::from(c) - xd.cos()).abs(),
        ] {
            worst = worst.max(e);
            sum2 += e * e;
        }
    }
    (worst, (sum2 / (2 * n) as f64).sqrt())
}

#[test]
fn sin_cos_absolute_error_over_the_exact_reduction_range() {
    let (m, rms) = trig_abs_error(f64::from(fmath::TRIG_EXACT_LIMIT), 1_000_000, 1);
    println!(
        "|x| <= {}: sin/cos max abs error {m:.3e}, rms {rms:.3e}",
        fmath::TRIG_EXACT_LIMIT
    );
    assert!(m <= 6.5e-8, "{m}");
    let (m, rms) = trig_abs_error(10.0, 1_000_000, 2);
    println!("|x| <= 10: sin/cos max abs error {m:.3e}, rms {rms:.3e}");
    assert!(m <= 6.5e-8, "{m}");
}

#[test]
fn sin_cos_error_growth_beyond_the_exact_range() {
    for hi in [1.0e6, f64::from(fmath::TRIG_LIMIT)] {
        let (m, rms) = trig_abs_error(hi, 200_000, 3);
        println!("|x| <= {hi:e}: sin/cos max abs error {m:.3e}, rms {rms:.3e}");
        // no better than the input itself: half the f32 spacing of x at the top of the range
        let half_ulp_x = 0.5 * ulp_of(hi);
        println!("  (half the f32 spacing of x there: {half_ulp_x:.3e})");
        assert!(m <= half_ulp_x + 6.5e-8, "{m}");
    }
}

#[test]
fn sin_cos_special_values() {
    for x in [f32::NAN, f32::INFINITY, -f32::INFINITY, 1.0e7, -7.0e6] {
        assert!(fmath::sin(x).is_nan() && fmath::cos(x).is_nan(), "{x}");
    }
    assert_eq!(fmath::sin(0.0).to_bits(), 0.0f32.to_bits());
    assert_eq!(fmath::sin(-0.0).to_bits(), (-0.0f32).to_bits());
    assert_eq!(fmath::cos(0.0), 1.0);
    assert_eq!(fmath::sin(1.0e-30), 1.0e-30);
}

#[test]
fn tan_near_zero_within_2_ulp() {
    let (e, x) = max_ulp(std::f32::consts::FRAC_PI_4, STRIDE, fmath::tan, f64::tan);
    println!("|x| <= pi/4: tan max {e:.3} ulp (x = {x:e})");
    assert!(e <= 2.0);
}

#[test]
fn atan_within_2_4_ulp_on_every_sampled_f32() {
    let (e, x) = max_ulp(f32::MAX, STRIDE, fmath::atan, f64::atan);
    println!("all f32: atan max {e:.3} ulp (x = {x:e})");
    assert!(e <= 2.4);
    assert_eq!(fmath::atan(f32::INFINITY), std::f32::consts::FRAC_PI_2);
    assert_eq!(fmath::atan(-f32::INFINITY), -std::f32::consts::FRAC_PI_2);
    assert!(fmath::atan(f32::NAN).is_nan());
    assert_eq!(fmath::atan(-0.0).to_bits(), (-0.0f32).to_bits());
}

#[test]
fn atan2_within_2_4_ulp() {
    let mut rng = Rng(12345);
    let mut worst = (0.0, 0.0f32, 0.0f32);
    for _ in 0..2_000_000 {
        // magnitudes over 2^-40..2^40 each, any signs: y/x over 80 orders of magnitude
        let y = (rng.unit().signum() * 2f64.powf(rng.unit() * 40.0)) as f32;
        let x = (rng.unit().signum() * 2f64.powf(rng.unit() * 40.0)) as f32;
        let e = ulp_err(fmath::atan2(y, x), f64::from(y).atan2(f64::from(x)));
        if e > worst.0 {
            worst = (e, y, x);
        }
    }
    // near-equal magnitudes and the octant boundaries
    for i in 0..200_000 {
        let x = 1.0 + i as f32 * 1.0e-5;
        for (y, x) in [
            (x, 1.0),
            (1.0, x),
            (x * 0.414_213_57, 1.0),
            (x * 2.414_213_5, -1.0),
        ] {
            let e = ulp_err(fmath::atan2(y, x), f64::from(y).atan2(f64::from(x)));
            if e > worst.0 {
                worst = (e, y, x);
            }
        }
    }
    println!(
        "atan2 max {:.3} ulp at (y, x) = ({:e}, {:e})",
        worst.0, worst.1, worst.2
    );
    assert!(worst.0 <= 2.4);
}

#[test]
fn atan2_special_values_follow_c99() {
    let pi = std::f32::consts::PI;
    let cases = [
        (0.0, 0.0, 0.0),
        (-0.0, 0.0, -0.0),
        (0.0, -0.0, pi),
        (-0.0, -0.0, -pi),
        (0.0, -1.0, pi),
        (-0.0, -1.0, -pi),
        (1.0, 0.0, pi / 2.0),
        (-1.0, -0.0, -pi / 2.0),
        (f32::INFINITY, f32::INFINITY, pi / 4.0),
        (f32::INFINITY, -f32::INFINITY, 3.0 * pi / 4.0),
        (-f32::INFINITY, 1.0, -pi / 2.0),
        (1.0, f32::INFINITY, 0.0),
        (1.0, -f32::INFINITY, pi),
        (f32::MAX, f32::MAX, pi / 4.0),
        (f32::MAX, -f32::MAX / 2.0, 2.034_443_9),
    ];
    for (y, x, want) in cases {
        let got = fmath::atan2(y, x);
        assert_eq!(
            got.to_bits(),
            want.to_bits(),
            "atan2({y}, {x}) = {got}, want {want}"
        );
    }
    assert!(fmath::atan2(f32::NAN, 1.0).is_nan() && fmath::atan2(1.0, f32::NAN).is_nan());
}

#[test]
fn asin_acos_within_2_5_ulp_on_every_sampled_f32() {
    let (ea, xa) = max_ulp(1.0, STRIDE, fmath::asin, f64::asin);
    let (ec, xc) = max_ulp(1.0, STRIDE, fmath::acos, f64::acos);
    println!("-1..=1: asin max {ea:.3} ulp (x = {xa:e}), acos max {ec:.3} ulp (x = {xc:e})");
    assert!(ea <= 2.5 && ec <= 1.2);
    for x in [1.000_000_1, -1.000_000_1, f32::NAN, f32::INFINITY] {
        assert!(fmath::asin(x).is_nan() && fmath::acos(x).is_nan());
    }
    assert_eq!(fmath::asin(1.0), std::f32::consts::FRAC_PI_2);
    assert_eq!(fmath::acos(-1.0), std::f32::consts::PI);
    assert_eq!(fmath::acos(1.0), 0.0);
}

/// `fmath::sqrt(x)` has the bits of the host's IEEE `f32::sqrt(x)`, or both are NaN (IEEE
/// leaves the NaN payload open).
fn sqrt_matches_ieee(x: f32) -> bool {
    let (got, want) = (fmath::sqrt(x), x.sqrt());
    got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan())
}

/// Dense sample (the default suite): every 127th of the 2³² bit patterns (both signs, NaNs), every
/// subnormal and the first 2²³ normal numbers (the normalisation path and the exponent parity),
/// the last 2²⁰ finite f32 and the special values.
#[test]
fn sqrt_is_correctly_rounded_on_sampled_f32() {
    let mut n = 0u64;
    for b in (0..=u32::MAX)
        .step_by(127)
        .chain(0..0x0100_0000)
        .chain(0x7f70_0000..=0x7f80_0000)
    {
        let x = f32::from_bits(b);
        assert!(sqrt_matches_ieee(x), "sqrt({x:e}) (bits {b:#010x})");
        n += 1;
    }
    println!("sqrt: bit-identical to IEEE sqrt on {n} sampled bit patterns");
    for x in [
        0.0f32,
        -0.0,
        f32::INFINITY,
        f32::MIN_POSITIVE,
        1.0e-45,
        f32::MAX,
        4.0,
        2.0,
    ] {
        assert_eq!(fmath::sqrt(x).to_bits(), x.sqrt().to_bits(), "sqrt({x:e})");
    }
    for x in [-1.0f32, -1.0e-45, -f32::INFINITY, f32::NAN, -f32::NAN] {
        assert!(fmath::sqrt(x).is_nan());
    }
}

/// Circular distance between two angles (rad).
fn angle_diff(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(std::f64::consts::TAU);
    d.min(std::f64::consts::TAU - d)
}

#[test]
fn wrap_two_pi_is_accurate_and_in_range() {
    let mut rng = Rng(777);
    let mut worst = (0.0f64, 0.0f32);
    for i in 0..1_000_000 {
        let x = if i % 2 == 0 {
            rng.unit() * 411_774.0
        } else {
            rng.unit() * 20.0
        } as f32;
        let r = fmath::wrap_two_pi(x);
        assert!((0.0..std::f32::consts::TAU).contains(&r), "wrap({x}) = {r}");
        let e = angle_diff(f64::from(r), f64::from(x));
        if e > worst.0 {
            worst = (e, x);
        }
    }
    println!(
        "|x| <= 411774: wrap_two_pi max abs error {:.3e} (x = {})",
        worst.0, worst.1
    );
    assert!(worst.0 <= 4.3e-7);
    assert!(fmath::wrap_two_pi(f32::NAN).is_nan() && fmath::wrap_two_pi(f32::INFINITY).is_nan());
    assert!((0.0..std::f32::consts::TAU).contains(&fmath::wrap_two_pi(3.0e30)));
    assert_eq!(fmath::wrap_two_pi(-0.0), 0.0);
}

// ---- exhaustive (every f32 of the domain), ignored by default ----

/// Every one of the 2³² bit patterns, on every available core (about 3 minutes on 2 cores).
#[test]
#[ignore = "exhaustive, minutes in release: cargo test --release --test fmath -- --ignored"]
fn exhaustive_sqrt() {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get()) as u64;
    let chunk = (1u64 << 32).div_ceil(threads);
    std::thread::scope(|scope| {
        for t in 0..threads {
            scope.spawn(move || {
                let hi = ((t + 1) * chunk).min(1 << 32);
                for b in t * chunk..hi {
                    let x = f32::from_bits(b as u32);
                    assert!(sqrt_matches_ieee(x), "sqrt({x:e}) (bits {b:#010x})");
                }
            });
        }
    });
    println!("sqrt: bit-identical to IEEE sqrt on all 2^32 bit patterns (NaN as NaN)");
}

#[test]
#[ignore = "exhaustive, minutes in release: cargo test --release --test fmath -- --ignored"]
fn exhaustive_sin_cos_reduced_range() {
    let (es, xs) = max_ulp(std::f32::consts::FRAC_PI_4, 1, fmath::sin, f64::sin);
    let (ec, xc) = max_ulp(std::f32::consts::FRAC_PI_4, 1, fmath::cos, f64::cos);
    println!(
        "every f32 |x| <= pi/4: sin max {es:.3} ulp (x = {xs:e}), cos max {ec:.3} ulp (x = {xc:e})"
    );
    assert!(es <= 1.0 && ec <= 1.0);
}

#[test]
#[ignore = "exhaustive, minutes in release: cargo test --release --test fmath -- --ignored"]
fn exhaustive_atan() {
    let (e, x) = max_ulp(f32::MAX, 1, fmath::atan, f64::atan);
    println!("every f32: atan max {e:.3} ulp (x = {x:e})");
    assert!(e <= 2.4);
}

#[test]
#[ignore = "exhaustive, minutes in release: cargo test --release --test fmath -- --ignored"]
fn exhaustive_asin_acos() {
    let (ea, xa) = max_ulp(1.0, 1, fmath::asin, f64::asin);
    let (ec, xc) = max_ulp(1.0, 1, fmath::acos, f64::acos);
    println!(
        "every f32 in -1..=1: asin max {ea:.3} ulp (x = {xa:e}), acos max {ec:.3} ulp (x = {xc:e})"
    );
    assert!(ea <= 2.5 && ec <= 1.2);
}

/// `fmath::min`/`max` agree with `f32::min`/`max` on every pair of non-NaN values (signed zeros:
/// either zero may come back, as for `f32::min`); with a NaN, `min` returns its first operand and
/// `max` its second (documented).
#[test]
fn min_max() {
    let values = [
        f32::NEG_INFINITY,
        -3.5,
        -1.0,
        -f32::MIN_POSITIVE,
        -0.0,
        0.0,
        1e-45,
        0.95,
        1.0,
        f32::MAX,
        f32::INFINITY,
    ];
    for &a in &values {
        for &b in &values {
            assert_eq!(acs::fmath::min(a, b), a.min(b), "{a} {b}");
            assert_eq!(acs::fmath::max(a, b), a.max(b), "{a} {b}");
        }
        // NaN: `min` returns its first argument, `max` its second (one `a > b`, `a >= b`
        // comparison each, which the MSP430 evaluates as the host does with `b` a constant)
        assert!(acs::fmath::min(f32::NAN, a).is_nan());
        assert_eq!(acs::fmath::min(a, f32::NAN).to_bits(), a.to_bits());
        assert_eq!(acs::fmath::max(f32::NAN, a).to_bits(), a.to_bits());
        assert!(acs::fmath::max(a, f32::NAN).is_nan());
    }
}
