//! f32 elementary functions used by the flight code: the single place where the crate's
//! transcendental functions come from.
//!
//! Every flight module calls these functions rather than `libm` directly. On the MSP430 (no FPU,
//! 16-bit) `libm`'s `sinf`, `atan2f`, `sqrtf`… compute internally in f64 and cost
//! 60 000–200 000 cycles a call (`docs/firmware.md`); the kernels here use
//! **f32 operations only** (no f64 anywhere) and a handful of multiplications, so they cost a
//! few thousand cycles (measured by `firmware/msp430-bench`, see `docs/firmware.md`).
//!
//! ## Method
//! - **Range reduction** (sin, cos, sincos, tan, [`wrap_two_pi`]): Cody–Waite (W. J. Cody and
//!   W. Waite, *Software Manual for the Elementary Functions*, 1980, ch. 8): `k = round(x·2/π)`,
//!   `r = x − k·C₁ − k·C₂ − k·C₃ − k·C₄` where `C₁ + C₂ + C₃ + C₄ = π/2` to 2⁻⁵⁶ and `C₁..C₃`
//!   carry 8 significant bits each, so `k·Cᵢ` is exact in f32 for `|k| < 2¹⁶`. Full accuracy for
//!   `|x| ≤ `[`TRIG_EXACT_LIMIT`] (102 943 rad); beyond, below [`TRIG_LIMIT`] (6.52·10⁶ rad), the
//!   products `k·Cᵢ` round and the absolute error grows about linearly with `|x|` (measured
//!   below); beyond that (where adjacent f32 are more than 0.5 rad apart, no angle is left) and for
//!   non-finite input the result is NaN.
//! - **Polynomials**: minimax (relative error) on the reduced interval, derived by
//!   `tools/fmath_coeffs.py` (Lawson's algorithm in f64, coefficients rounded to f32).
//!   They agree with S. L. Moshier's Cephes single-precision sets (`sinf.c`, `atanf.c`,
//!   `asinf.c`, Cephes Math Library 2.2, 1992) to the printed digits.
//! - **sqrt**: exact digit-by-digit integer square root of the significand on 16-bit words (a
//!   16-bit integer square root for the top 8 root bits, then fdlibm's `e_sqrtf.c` recurrence,
//!   Sun Microsystems 1993, for the 17 others): correctly rounded (round to nearest even), no
//!   multiplication, no 64-bit operation.
//!
//! ## Measured accuracy (host, against f64 `std` functions)
//! Reproduce: `cargo test --release --test fmath -- --nocapture` (dense sampling: every 997th f32
//! bit pattern of the domain, or 10⁶ uniform samples) and
//! `cargo test --release --test fmath -- --ignored --nocapture` (exhaustive: every f32 of the
//! domain; about 45 minutes on a loaded 2-core machine).
//!
//! | function | domain | max error | how |
//! |---|---|---|---|
//! | [`sin`], [`cos`], [`sincos`] | \|x\| ≤ π/4 | 0.79 ulp (sin), 0.75 ulp (cos) | exhaustive |
//! | | \|x\| ≤ 102 943 | 6.5·10⁻⁸ absolute, RMS 1.7·10⁻⁸ | 10⁶ samples |
//! | | \|x\| < 6.52·10⁶ | ½ ulp of `x` (the input's own spacing: 0.25 at the top) | 2·10⁵ samples |
//! | [`tan`] | \|x\| ≤ π/4 | 1.9 ulp | dense |
//! | [`atan`] | all f32 | 2.30 ulp | exhaustive |
//! | [`atan2`] | y/x over 80 decades, all signs | 2.30 ulp | 2.8·10⁶ samples |
//! | [`asin`], [`acos`] | −1..=1 | 2.44 ulp, 1.19 ulp | exhaustive |
//! | [`sqrt`] | all 2³² bit patterns | correctly rounded (bit-identical to IEEE `sqrt`) | exhaustive |
//! | [`wrap_two_pi`] | \|x\| ≤ 411 774 | 4.2·10⁻⁷ absolute | 10⁶ samples |
//!
//! ## Float comparisons in flight code (NaN on the MSP430)
//! On the MSP430 every ordered float comparison is one call of `__mspabi_cmpf` and a sign test,
//! and the helper answers "less" for a NaN operand: what reaches the code generator as `a < b`
//! or `a <= b` is TRUE for a NaN, as `!(a > b)`, `!(a >= b)` are; `a > b`, `a >= b`, `==`, `!=`
//! are correct (`firmware/eabi/README.md`). LLVM moves a constant to the right of a comparison
//! (`0.0 > x` becomes `x < 0.0`), so writing `b > a` does not help when `b` is a constant. Flight
//! code therefore writes its float comparisons so that host and target agree for a NaN:
//! - constant on the right: `x > c`, `x >= c` (false for a NaN), `!(x >= c)` for "x < c or NaN",
//!   `!(x > c)` for "x <= c or NaN" (true for a NaN, on the host as on the MSP430);
//! - two variables: `b > a` for `a < b`, `b >= a` for `a <= b` (false for a NaN);
//! - [`min`], [`max`] instead of `f32::min`, `max`, `clamp`; never `(lo..hi).contains(&x)`.
//!
//! `tools/float_compare_check.py` rejects `<`, `<=`, `min`, `max`, `clamp` and range `contains`
//! in flight code, and with `--ir` checks the flight image's optimised LLVM IR: no `fcmp olt`,
//! `ole`, `ugt`, `uge` (the four predicates the MSP430 evaluates wrongly for a NaN) may reach the
//! code generator.
//!
//! `pow`, `exp` and `floor` forward to `libm`'s f32 routines (`powf`, `expf` are fdlibm's
//! f32-only algorithms; `floorf` works on the bits); `abs` clears the sign bit.

use core::f32::consts::{FRAC_2_PI, FRAC_PI_2, FRAC_PI_4, PI};

/// `|x|` up to which the sine/cosine range reduction is exact (quadrant count `k < 2¹⁶`).
pub const TRIG_EXACT_LIMIT: f32 = 102943.;
/// `|x|` from which sine and cosine return NaN (6 520 832 = 0x4AC7_0000, so that the test is one
/// on the high 16 bits; the quadrant count stays below 2²², and the f32 spacing of `x` is
/// 0.5 rad from 2²² on: beyond, no angle is left).
pub const TRIG_LIMIT: f32 = 6_520_832.0;

/// Below this |x| (2⁻¹²), sin x rounds to x (x³/6 < ½ ulp) and cos x to 1; keeps sin(−0) = −0.
const SIN_TINY: f32 = 0.000_244_140_63;
/// 0.785 156 25 (0x3F49_0000), just below π/4: below it the reduction is skipped (`k = 0`,
/// `r = x`); between it and π/4 the reduction also gives `k = 0` and `r = x` (checked for each of
/// these 4 060 f32), so the results are those of a threshold at π/4.
const PIO4_BELOW: f32 = 0.785_156_25;
/// From this |x| or |y| on (≈ 1.03·10³⁰, 0x7150_0000), [`atan2`] scales its arguments down.
const ATAN2_HUGE: f32 = 1.029_966_1e30;
/// 1.5·2²³: adding and subtracting it rounds an f32 of magnitude < 2²² to the nearest integer,
/// and the low mantissa bits of the sum hold that integer (two's complement).
const ROUND_MAGIC: f32 = 12_582_912.0;
/// π/2 = `PIO2_1 + PIO2_2 + PIO2_3 + PIO2_4` (residual 5·10⁻¹⁷); the first three have 8
/// significant bits.
const PIO2_1: f32 = 1.5703125;
const PIO2_2: f32 = 0.00048446655;
const PIO2_3: f32 = -6.4074993e-7;
const PIO2_4: f32 = 9.920936e-10;
/// π/2 = `PIO2_S1 + PIO2_S2` (residual 1.7·10⁻¹³), `PIO2_S1` with 16 significant bits: the
/// short reduction for |k| < 2⁸, i.e. |x| < [`PIO2_SHORT_LIMIT`].
const PIO2_S1: f32 = 1.5708008;
const PIO2_S2: f32 = -4.454455e-6;
/// |x| below which the two-piece reduction is used (k ≤ 255).
const PIO2_SHORT_LIMIT: f32 = 400.0;
/// 2π split the same way (the pieces are 4 × those of π/2).
const TWO_PI_1: f32 = 6.28125;
const TWO_PI_2: f32 = 0.0019378662;
const TWO_PI_3: f32 = -2.5629997e-6;
const TWO_PI_4: f32 = 3.9683745e-9;
/// 1/(2π) rounded to f32.
const FRAC_1_2PI: f32 = 0.15915494;
/// `|x|` up to which [`wrap_two_pi`]'s reduction is exact (`k < 2¹⁶`).
const WRAP_EXACT_LIMIT: f32 = 411_774.0;

/// Low parts: `π − PI`, `π/2 − FRAC_PI_2`, `π/4 − FRAC_PI_4` (f32 `PI` etc. are the rounded
/// values).
const PI_LO: f32 = -8.742278e-8;
const PI_2_LO: f32 = -4.371139e-8;
const PI_4_LO: f32 = -2.1855694e-8;
/// 3π/4 = `PI_3_4 + PI_3_4_LO`.
const PI_3_4: f32 = 2.3561945;
const PI_3_4_LO: f32 = -5.9624403e-9;

/// tan(π/8) and tan(3π/8): the [`atan`] reduction thresholds.
const TAN_PI_8: f32 = 0.41421357;
const TAN_3PI_8: f32 = 2.4142137;

/// sin r ≈ r + r³·(S0 + r²·(S1 + r²·S2)) on |r| ≤ π/4, max relative approximation error
/// 8.3·10⁻⁹ (`fmath_coeffs.py`; Cephes `sinf.c`).
const SIN_P0: f32 = -0.16666655;
const SIN_P1: f32 = 0.00833216;
const SIN_P2: f32 = -0.00019515284;
/// cos r ≈ 1 − r²/2 + r⁴·(C0 + r²·(C1 + r²·C2)) on |r| ≤ π/4, max relative approximation error
/// 1.7·10⁻¹⁰ (`fmath_coeffs.py`; Cephes `sinf.c`).
const COS_P0: f32 = 0.041666646;
const COS_P1: f32 = -0.0013887316;
const COS_P2: f32 = 2.4433157e-5;
/// atan u ≈ u + u³·P(u²) on |u| ≤ tan(π/8), max relative approximation error 2.2·10⁻⁸
/// (`fmath_coeffs.py`; Cephes `atanf.c`).
const ATAN_P0: f32 = -0.3333295;
const ATAN_P1: f32 = 0.1997771;
const ATAN_P2: f32 = -0.1387768;
const ATAN_P3: f32 = 0.08053723;
/// asin x ≈ x + x³·P(x²) on |x| ≤ 1/2, max relative approximation error 5.9·10⁻⁹
/// (`fmath_coeffs.py`; Cephes `asinf.c`).
const ASIN_P0: f32 = 0.16666752;
const ASIN_P1: f32 = 0.074952975;
const ASIN_P2: f32 = 0.045470376;
const ASIN_P3: f32 = 0.024179516;
const ASIN_P4: f32 = 0.042166304;

/// sin r for |r| ≤ π/4 (plus the reduction's rounding slack).
#[inline(always)]
fn sin_kernel(r: f32) -> f32 {
    let z = r * r;
    r + r * z * (SIN_P0 + z * (SIN_P1 + z * SIN_P2))
}

/// cos r for |r| ≤ π/4 (plus slack).
#[inline(always)]
fn cos_kernel(r: f32) -> f32 {
    let z = r * r;
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    // (1 − w) − hz recovers the rounding error of w (fdlibm `__kernel_cos`)
    let tail = z * z * (COS_P0 + z * (COS_P1 + z * COS_P2));
    w + (((1.0 - w) - hz) + tail)
}

/// Cody–Waite reduction: `x = k·π/2 + r`, `|r| ≤ π/4` (slightly more after rounding); returns
/// `(r, k mod 4)`, or `None` for non-finite `x` or `|x| ≥ TRIG_LIMIT`.
///
/// Comparisons are made on the high 16 bits of `|x|` (for non-negative floats, including +∞ and
/// NaN above it, the integer order is the numeric order; the thresholds have zero low words):
/// on the MSP430 a float comparison is a helper call, a 16-bit integer one two instructions.
#[inline(always)]
fn reduce_pio2(x: f32) -> Option<(f32, u32)> {
    let ahi = high_word(abs(x));
    if high_word(PIO4_BELOW) > ahi {
        return Some((x, 0));
    }
    if ahi >= high_word(TRIG_LIMIT) {
        return None;
    }
    let biased = x * FRAC_2_PI + ROUND_MAGIC;
    let quadrant = biased.to_bits() & 3;
    let k = biased - ROUND_MAGIC;
    let r = if high_word(PIO2_SHORT_LIMIT) > ahi {
        // |k| < 2⁸: two pieces (16 + 24 bits of π/2) suffice, k·PIO2_S1 is exact
        (x - k * PIO2_S1) - k * PIO2_S2
    } else {
        // x − k·C₁ and then − k·C₂ are exact; the two small products are summed first
        (x - k * PIO2_1 - k * PIO2_2) - (k * PIO2_3 + k * PIO2_4)
    };
    Some((r, quadrant))
}

/// Sine of `x` (radians): the first of [`sincos`] (one kernel in the flight image; a sine costs
/// a cosine kernel more, ≈ 1 900 MSP430 cycles without the multiplier).
///
/// Cody–Waite reduction to `|r| ≤ π/4` (module docs) then a degree-7 odd minimax polynomial.
/// Measured (`tests/fmath.rs`): max 0.79 ulp for |x| ≤ π/4 (exhaustive); max absolute error
/// 6.5·10⁻⁸ for |x| ≤ [`TRIG_EXACT_LIMIT`]; beyond, below [`TRIG_LIMIT`], half the f32 spacing
/// of `x` (the input's own resolution); NaN for non-finite `x` or |x| ≥ [`TRIG_LIMIT`].
#[inline]
pub fn sin(x: f32) -> f32 {
    sincos(x).0
}

/// Cosine of `x` (radians): the second of [`sincos`]. Method and measured error as [`sin`].
#[inline]
pub fn cos(x: f32) -> f32 {
    sincos(x).1
}

/// `(sin x, cos x)` of `x` (radians), sharing one range reduction: the sine and cosine kernels
/// of the reduced angle, rotated by its quadrant. Method and measured error as [`sin`] (which
/// with [`cos`] returns the parts of this pair).
#[cfg_attr(target_arch = "msp430", inline(never))]
#[cfg_attr(not(target_arch = "msp430"), inline)]
pub fn sincos(x: f32) -> (f32, f32) {
    if high_word(SIN_TINY) > high_word(abs(x)) {
        return (x, 1.0);
    }
    match reduce_pio2(x) {
        Some((r, q)) => {
            let (s, c) = (sin_kernel(r), cos_kernel(r));
            // quadrant q: (s, c) turned by q·π/2; odd q swaps, q ≥ 2 negates
            let (s, c) = if q & 1 == 0 { (s, c) } else { (c, -s) };
            if q & 2 == 0 {
                (s, c)
            } else {
                (-s, -c)
            }
        }
        None => (f32::NAN, f32::NAN),
    }
}

/// Tangent of `x` (radians): `sin x / cos x` from [`sincos`]. Measured: max 1.9 ulp for
/// |x| ≤ π/4; near the poles the relative error follows cos's absolute error (6·10⁻⁸ / |cos x|).
#[cfg_attr(target_arch = "msp430", inline(never))]
#[cfg_attr(not(target_arch = "msp430"), inline)]
pub fn tan(x: f32) -> f32 {
    let (s, c) = sincos(x);
    s / c
}

/// Polynomial part of the arctangent: atan u for |u| ≤ tan(π/8). Out of line on the MSP430,
/// where LLVM would otherwise copy it into each octant of [`atan2`].
#[cfg_attr(target_arch = "msp430", inline(never))]
#[cfg_attr(not(target_arch = "msp430"), inline(always))]
fn atan_kernel(u: f32) -> f32 {
    let z = u * u;
    u + u * z * (ATAN_P0 + z * (ATAN_P1 + z * (ATAN_P2 + z * ATAN_P3)))
}

/// atan(n/d) for `0 ≤ n`, `0 < d` (or `n > 0`, `d = 0`), finite, with **one** division and
/// one polynomial: `n ≤ d·tan(π/8)`: `p = atan(n/d)`; `n ≤ d·tan(3π/8)`: `π/4 + atan((n−d)/(n+d))`;
/// else `π/2 + atan(−d/n)`, each argument in `[−tan(π/8), tan(π/8)]`. The angle is summed as
/// `hi + (lo + p)` (`hi + lo` the octant's angle in two pieces), or, if `mirror` (x < 0 in
/// [`atan2`]), `π − angle = (π − hi) + ((π_lo − lo) − p)`, folded into the constants so that no
/// extra rounding occurs.
#[inline(always)]
fn atan_octants(n: f32, d: f32, mirror: bool) -> f32 {
    // n, d ≥ 0: compare bit patterns (module docs of `reduce_pio2`)
    let nb = n.to_bits();
    let (octant, num, den) = if (d * TAN_PI_8).to_bits() >= nb {
        (0, n, d)
    } else if (d * TAN_3PI_8).to_bits() >= nb {
        (1, n - d, n + d)
    } else {
        (2, -d, n)
    };
    let p = atan_kernel(num / den);
    let (hi, lo) = match (octant, mirror) {
        (0, false) => (0.0, 0.0),
        (1, false) => (FRAC_PI_4, PI_4_LO),
        (_, false) => (FRAC_PI_2, PI_2_LO),
        (0, true) => (PI, PI_LO),
        (1, true) => (PI_3_4, PI_3_4_LO),
        (_, true) => (FRAC_PI_2, PI_2_LO),
    };
    hi + (lo + if mirror { -p } else { p })
}

/// Arctangent, radians in −π/2..=π/2: [`atan2`]`(x, 1)` (one kernel in the flight image; the
/// division by 1 of its first octant, exact, costs ≈ 400 MSP430 cycles).
///
/// Octant reduction with one division to |u| ≤ tan(π/8), then a degree-9 odd minimax
/// polynomial. Measured (`tests/fmath.rs`, every f32): max 2.30 ulp. `atan(±∞) = ±π/2`,
/// NaN → NaN.
#[inline]
pub fn atan(x: f32) -> f32 {
    atan2(x, 1.0)
}

/// Four-quadrant arctangent of `y / x`, radians in −π..=π.
///
/// Octant reduction of `(|y|, |x|)` with one division to |u| ≤ tan(π/8), a degree-9 odd minimax
/// polynomial, then the quadrant from the signs. Special values as IEEE/C99 `atan2f`:
/// `atan2(±0, +0) = ±0`, `atan2(±0, −0) = ±π`, `atan2(±∞, ±∞) = ±π/4, ±3π/4`; NaN in → NaN
/// out. Measured (`tests/fmath.rs`, dense sampling of all f32 pairs over 80 orders of magnitude
/// of y/x): max 2.30 ulp.
#[cfg_attr(target_arch = "msp430", inline(never))]
#[cfg_attr(not(target_arch = "msp430"), inline)]
pub fn atan2(y: f32, x: f32) -> f32 {
    let mut ax = abs(x);
    let mut ay = abs(y);
    let (xb, yb) = (ax.to_bits(), ay.to_bits());
    let inf = f32::INFINITY.to_bits();
    if xb > inf || yb > inf {
        return x + y;
    }
    if xb == inf && yb == inf {
        // atan2(±∞, ±∞) = ±π/4 or ±3π/4: the ratio of equal magnitudes
        ax = 1.0;
        ay = 1.0;
    } else if high_word(ax) >= high_word(ATAN2_HUGE) || high_word(ay) >= high_word(ATAN2_HUGE) {
        // keep d·tan(3π/8) and n + d finite; exact (power of two)
        ax *= 1.0 / 1024.0;
        ay *= 1.0 / 1024.0;
    }
    let mirror = x.is_sign_negative();
    let a = if yb == 0 {
        if mirror {
            PI
        } else {
            0.0
        }
    } else {
        atan_octants(ay, ax, mirror)
    };
    if y.is_sign_negative() {
        -a
    } else {
        a
    }
}

/// asin x for |x| ≤ 1/2. Out of line on the MSP430, where LLVM would otherwise copy it into
/// both branches of [`asin`].
#[cfg_attr(target_arch = "msp430", inline(never))]
#[cfg_attr(not(target_arch = "msp430"), inline(always))]
fn asin_kernel(x: f32) -> f32 {
    let z = x * x;
    x + x * z * (ASIN_P0 + z * (ASIN_P1 + z * (ASIN_P2 + z * (ASIN_P3 + z * ASIN_P4))))
}

/// Arcsine, radians in −π/2..=π/2; NaN outside −1..=1 (clamp first where rounding may push past
/// ±1).
///
/// |x| ≤ 1/2: degree-11 odd minimax polynomial; |x| > 1/2: `π/2 − 2·asin(√((1−|x|)/2))` (exact
/// [`sqrt`]), the same polynomial. Measured (`tests/fmath.rs`, every f32 in −1..=1): max 2.44
/// ulp. (As [`atan2`]`(x, √(1 − x²))` it would share the arctangent's kernel and save 188 B of
/// flight code, but measured 2.79 ulp, every f32: the arctangent's own 2.3 ulp at its octant
/// boundary plus the rounding of the cosine; `2·atan2(x, 1 + √(1 − x²))`: 2.68 ulp.)
#[cfg_attr(target_arch = "msp430", inline(never))]
#[cfg_attr(not(target_arch = "msp430"), inline)]
pub fn asin(x: f32) -> f32 {
    let ax = abs(x);
    let abits = ax.to_bits();
    if abits > 1.0f32.to_bits() {
        return f32::NAN;
    }
    let small = 0.5f32.to_bits() >= abits;
    let u = if small { ax } else { sqrt(0.5 * (1.0 - ax)) };
    let p = asin_kernel(u);
    let a = if small {
        p
    } else {
        FRAC_PI_2 - (2.0 * p - PI_2_LO)
    };
    if x.is_sign_negative() {
        -a
    } else {
        a
    }
}

/// Arccosine, radians in 0..=π; NaN outside −1..=1 (clamp first where rounding may push past ±1).
///
/// |x| ≤ 1/2: `π/2 − asin x`; x > 1/2: `2·asin(√((1−x)/2))`; x < −1/2: `π − 2·asin(√((1+x)/2))`.
/// Measured (`tests/fmath.rs`, every f32 in −1..=1): max 1.19 ulp.
#[cfg_attr(target_arch = "msp430", inline(never))]
#[cfg_attr(not(target_arch = "msp430"), inline)]
pub fn acos(x: f32) -> f32 {
    let ax = abs(x);
    let abits = ax.to_bits();
    if abits > 1.0f32.to_bits() {
        return f32::NAN;
    }
    if 0.5f32.to_bits() >= abits {
        FRAC_PI_2 - (asin_kernel(x) - PI_2_LO)
    } else {
        let s = sqrt(0.5 * (1.0 - ax));
        let a = 2.0 * asin_kernel(s);
        if !x.is_sign_negative() {
            a
        } else {
            PI - (a - PI_LO)
        }
    }
}

/// Square root, correctly rounded (round to nearest even: bit-identical to IEEE-754 `sqrt`);
/// `sqrt(−0) = −0`, `sqrt(+∞) = +∞`, NaN for negative input or NaN.
///
/// Exact digit-by-digit integer method on the bits of `x` (module docs), written on 16-bit words
/// for the MSP430, whose compiled 32-bit shifts and carries cost 10–15 instructions each: the
/// root `q` (25 bits: 24 of the result and the rounding bit) of the radicand `N = X₀·2²⁴`,
/// `X₀ = M·2ᵏ ∈ [2²⁴, 2²⁶)` (`M` the 24-bit significand, `k ∈ {1, 2}` making the exponent even),
/// is found in two phases:
/// 1. the top 8 bits, `q₁ = ⌊√(X₀ >> 10)⌋`, by the classic shift-and-subtract square root of a
///    16-bit integer (16-bit words only; its first step always succeeds and is skipped);
/// 2. the 17 others by fdlibm's recurrence (`e_sqrtf.c`, Sun Microsystems 1993) from its state
///    after 8 bits: with `s = 2q`, the remainder `X = (N − q²)/r` of root bit `r` is compared with
///    `t = s + r`; if `X ≥ t` then `X −= t`, `s += 2r`; `X` doubles and `r` halves. `X < 2²⁸`
///    and `t` are word pairs; `X − t` is tested by the sign of its high word.
///
/// No square root of an f32 lies halfway between two f32 (`q` odd would give `q²` odd, but `N`
/// is even), so rounding to nearest is `(q + 1) >> 1`: no remainder test. Subnormal input is
/// normalised first. No multiplication, no 64-bit operation.
///
/// Verified (`tests/fmath.rs`): bit-identical to the host's `f32::sqrt` on every one of the
/// 2³² bit patterns (NaN results compared as NaN; ignored exhaustive test), and on a dense
/// sample (every 127th pattern, all subnormals, special values) in the default suite.
/// MSP430 (`firmware/msp430-bench`, group `core`): about 1 050 cycles, no multiplication.
#[cfg_attr(target_arch = "msp430", inline(never))]
#[cfg_attr(not(target_arch = "msp430"), inline)]
pub fn sqrt(x: f32) -> f32 {
    let bits = x.to_bits();
    let hi = (bits >> 16) as u16;
    let lo = bits as u16;
    if hi >= 0x7f80 {
        // +∞, NaN, or the sign bit set
        return if bits == 0x7f80_0000 || bits == 0x8000_0000 {
            x
        } else {
            f32::NAN
        };
    }
    if hi | lo == 0 {
        return x;
    }
    // biased exponent `e`, significand `M = (mh, ml)` with its leading bit (bit 7 of `mh`)
    let mut e = (hi >> 7) as i16;
    let mut mh = hi & 0x7f;
    let mut ml = lo;
    if e == 0 {
        // subnormal: normalise (at most 23 steps)
        e = 1;
        while mh & 0x80 == 0 {
            (mh, ml) = double_words(mh, ml);
            e -= 1;
        }
    } else {
        mh |= 0x80;
    }
    // X₀ = M·2ᵏ, k = 2 for an odd unbiased exponent (even `e`), else 1: xt = X₀ >> 10 (16 bits),
    // xb = X₀ & 0x3ff
    let m8 = (mh << 8) | (ml >> 8);
    let (xt, xb) = if e & 1 == 0 {
        (m8, (ml << 2) & 0x3ff)
    } else {
        (m8 >> 1, (ml << 1) & 0x3ff)
    };
    // phase 1: res = q₁ = ⌊√xt⌋ ∈ [128, 256), n = xt − q₁² ≤ 2q₁; xt ≥ 2¹⁴, so the first step
    // (bit 2¹⁴) always succeeds
    let mut n = xt - 0x4000;
    let mut res: u16 = 0x4000;
    let mut one: u16 = 0x1000;
    while one != 0 {
        let t = res + one;
        if n >= t {
            n -= t;
            res = (res >> 1) + one;
        } else {
            res >>= 1;
        }
        one >>= 2;
    }
    // phase 2 from fdlibm's state at r = 2¹⁶: s = q₁·2¹⁸, X = n·2¹⁸ + xb·2⁸ (as word pairs)
    let mut sh = res << 2;
    let mut sl: u16 = 0;
    let mut xh = (n << 2) | (xb >> 8);
    let mut xl = xb << 8;
    // r = 2¹⁶: t = (sh + 1, 0)
    let th = sh + 1;
    if xh >= th {
        xh -= th;
        sh = th + 1;
    }
    (xh, xl) = double_words(xh, xl);
    // r = 2¹⁵ … 1: t = (sh, sl | r) (the bits of s lie above r); s += 2r
    let mut r: u16 = 0x8000;
    loop {
        let tl = sl | r;
        let dh = xh.wrapping_sub(sh).wrapping_sub(u16::from(tl > xl));
        if (dh as i16) >= 0 {
            xh = dh;
            xl = xl.wrapping_sub(tl);
            if r == 0x8000 {
                sh += 1;
            } else {
                sl |= r << 1;
            }
        }
        if r == 1 {
            break;
        }
        (xh, xl) = double_words(xh, xl);
        r >>= 1;
    }
    // q = s/2 ∈ [2²⁴, 2²⁵); rounded: (q + 1) >> 1 = (s + 2) >> 2, its leading bit adding 1 to
    // the exponent field (e − 127)/2 + 126 = (e + 125)/2, rounded down (`e` may be ≤ 0 here)
    let s = (u32::from(sh) << 16) | u32::from(sl);
    let m = (s + 2) >> 2;
    let ef = ((e + 125) >> 1) as u32;
    f32::from_bits(m + (ef << 23))
}

/// `(h, l)`, a 32-bit integer as two 16-bit words, doubled (`(h << 1 | l >> 15, l << 1)`).
#[inline(always)]
fn double_words(h: u16, l: u16) -> (u16, u16) {
    (h.wrapping_add(h).wrapping_add(l >> 15), l.wrapping_add(l))
}

/// Floor (`libm::floorf`, bit manipulation, exact).
#[inline]
pub fn floor(x: f32) -> f32 {
    libm::floorf(x)
}

/// The high 16 bits of the bit pattern of `x` (sign, exponent, top 7 significand bits).
#[inline(always)]
const fn high_word(x: f32) -> u16 {
    (x.to_bits() >> 16) as u16
}

/// Absolute value (clears the sign bit; exact, NaN stays NaN).
#[inline]
pub fn abs(x: f32) -> f32 {
    f32::from_bits(x.to_bits() & 0x7fff_ffff)
}

/// The smaller of `a` and `b`; `a` if either is NaN. One `a > b` comparison, which the MSP430
/// evaluates correctly for a NaN operand as long as `b` is not a constant while `a` is one (LLVM
/// puts constants on the right and would turn it into `b < a`, which is wrong for NaN there:
/// `firmware/eabi/README.md`); write the constant second, `min(x, 1.0)`. No call of `fminf`
/// (≈ 100 B of MSP430 flash). Exact.
#[inline]
pub fn min(a: f32, b: f32) -> f32 {
    if a > b {
        b
    } else {
        a
    }
}

/// The larger of `a` and `b`; `b` if either is NaN, so `max(x, 0.0)` is `0.0` for a NaN `x`
/// (on the host and on the MSP430 alike). One `a >= b` comparison: constant second, as for
/// [`min`]. Exact (`max(-0.0, 0.0)` is `-0.0`, `max(0.0, -0.0)` is `0.0`: the first of equals).
#[inline]
pub fn max(a: f32, b: f32) -> f32 {
    if a >= b {
        a
    } else {
        b
    }
}

/// `x` reduced to `[0, 2π)` (NaN and ±∞ give NaN).
///
/// Cody–Waite with a four-piece 2π (module docs): exact reduction for |x| ≤ 411 774 rad
/// (`k < 2¹⁶` turns); measured max absolute error 4.2·10⁻⁷ there (`tests/fmath.rs`): the
/// rounding of a result near 2π (½ ulp = 2.4·10⁻⁷) plus that of the reduction. Beyond, up to
/// 2.6·10⁷ rad, the error grows about linearly with |x|;
/// beyond that `x` has no fractional turn left in f32 and the result is `libm::fmodf(x, 2π_f32)`
/// (exact modulo the f32-rounded 2π). Relative to the previous `fmodf(x, TAU)` this is accurate
/// to the true 2π: `TAU` as f32 is 1.7·10⁻⁷ too large, an error of `k·1.7·10⁻⁷` rad after k turns.
#[cfg_attr(target_arch = "msp430", inline(never))]
#[cfg_attr(not(target_arch = "msp430"), inline)]
pub fn wrap_two_pi(x: f32) -> f32 {
    let ax = abs(x);
    let tau = core::f32::consts::TAU;
    if ax.to_bits() > (WRAP_EXACT_LIMIT * 64.0).to_bits() {
        if x.is_finite() {
            let r = libm::fmodf(x, tau);
            return if r >= 0.0 { r } else { r + tau };
        }
        return f32::NAN;
    }
    // k ≈ floor(x/2π) (round(x/2π − ½)), so that r lands in [0, 2π) without a final addition
    // but for rounding corners, which the two corrections below catch
    let biased = (x * FRAC_1_2PI - 0.5) + ROUND_MAGIC;
    let k = biased - ROUND_MAGIC;
    let mut r = (x - k * TWO_PI_1 - k * TWO_PI_2) - (k * TWO_PI_3 + k * TWO_PI_4);
    // sign and range tests on the bits (see `reduce_pio2`)
    if r.to_bits() & 0x8000_0000 != 0 {
        r += tau;
    }
    if r.to_bits() >= tau.to_bits() {
        // r ≥ 2π (k one too small) or −tiny + 2π rounded up to the f32 2π
        r = if r.to_bits() > tau.to_bits() {
            r - tau
        } else {
            0.0
        };
    }
    r
}

/// Power `x^y` (`libm::powf`: fdlibm's f32-only algorithm, max 1 ulp per its documentation).
#[cfg_attr(target_arch = "msp430", inline(never))]
#[cfg_attr(not(target_arch = "msp430"), inline)]
pub fn pow(x: f32, y: f32) -> f32 {
    libm::powf(x, y)
}

/// Natural exponential (`libm::expf`: fdlibm's f32-only algorithm, max 1 ulp per its
/// documentation).
#[cfg_attr(target_arch = "msp430", inline(never))]
#[cfg_attr(not(target_arch = "msp430"), inline)]
pub fn exp(x: f32) -> f32 {
    libm::expf(x)
}
