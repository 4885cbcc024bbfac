//! Double-f32 arithmetic ("double-single"): a value as the unevaluated sum `hi + lo` of two f32,
//! about 48 significant bits, for the one-time initialisations that need more than f32 on a core
//! without f64 hardware (the SGP4 secular rates). Only f32 operations: no f64 soft float.
//!
//! Source: T. J. Dekker, "A floating-point technique for extending the available precision",
//! Numer. Math. 18 (1971) 224–242: exact sum (`two_sum`, Knuth's branch-free form, TAOCP vol. 2
//! §4.2.2 Theorem B), exact product by Veltkamp's split into 12-bit halves (`two_prod`, Dekker's
//! `mul12`), and the double-length sum, product and quotient built on them (`add2`, `mul2`,
//! `div2`); square and cube roots by one Newton step in double length from the f32 root.
//! They rely on round-to-nearest f32 operations without contraction into FMA, as Rust and the
//! MSP430 EABI helpers of `firmware/eabi` provide.
//!
//! Precision (measured, `cargo test --lib orbit::dfloat`, against f64 on the host): relative
//! error below 2⁻⁴⁴ ≈ 6·10⁻¹⁴ for `+ − × ÷ sqrt cbrt` on the operands of SGP4's initialisation,
//! and below 10⁻¹⁴ absolute for `sin_pi_2` (|x| ≤ π/2): five to six decimal orders better than
//! f32, and within a few units of f64's last digit for what SGP4 needs (its rates to 10⁻¹³).
//!
//! f64 appears only as storage: [`Df::from_f64`] splits the bits of an f64 (a TLE field) with
//! integer operations, and [`Df::from_f64_const`] is for `const` items (evaluated by the
//! compiler, never at run time).
//!
//! | name | meaning |
//! |---|---|
//! | `hi` | the value rounded to f32 |
//! | `lo` | the rest, \|lo\| ≤ ulp(hi) |

use core::ops::{Add, Div, Mul, Neg, Sub};

/// `hi + lo`, two f32 whose sum carries about 48 significant bits.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(crate) struct Df {
    hi: f32,
    lo: f32,
}

/// Veltkamp's splitter for 24-bit significands: 2¹² + 1.
const SPLITTER: f32 = 4097.0;

/// `a + b` exactly, as a rounded sum and its error (Knuth, any order of magnitude).
#[inline]
fn two_sum(a: f32, b: f32) -> Df {
    let s = a + b;
    let bb = s - a;
    let e = (a - (s - bb)) + (b - bb);
    Df { hi: s, lo: e }
}

/// `a + b` exactly when |a| ≥ |b| (or a = 0) (Dekker's `fast two sum`).
#[inline]
fn fast_two_sum(a: f32, b: f32) -> Df {
    let s = a + b;
    Df {
        hi: s,
        lo: b - (s - a),
    }
}

/// `a` as the sum of two 12-bit halves (Veltkamp); |a| < 2¹¹⁵.
#[inline]
fn split(a: f32) -> (f32, f32) {
    let t = SPLITTER * a;
    let hi = t - (t - a);
    (hi, a - hi)
}

/// `a·b` exactly, as a rounded product and its error (Dekker's `mul12`).
#[inline(never)]
fn two_prod(a: f32, b: f32) -> Df {
    let p = a * b;
    let (ah, al) = split(a);
    let (bh, bl) = split(b);
    let e = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
    Df { hi: p, lo: e }
}

/// `2ⁿ` for −126 ≤ n ≤ 127 (exact, from the bits).
fn pow2(n: i32) -> f32 {
    f32::from_bits(((n + 127) as u32) << 23)
}

impl Df {
    /// Zero.
    pub(crate) const ZERO: Self = Self { hi: 0.0, lo: 0.0 };

    /// An f32, exactly.
    pub(crate) const fn from_f32(x: f32) -> Self {
        Self { hi: x, lo: 0.0 }
    }

    /// An f64 constant, for `const` items only (f64 arithmetic done by the compiler).
    pub(crate) const fn from_f64_const(x: f64) -> Self {
        let hi = x as f32;
        Self {
            hi,
            lo: (x - hi as f64) as f32,
        }
    }

    /// An f64 split into `hi + lo` with integer operations on its bits (no f64 arithmetic):
    /// 48 of its 53 significant bits (relative error below 2⁻⁴⁷). `None` if `x` is not finite or
    /// beyond the f32 range (|x| ≥ 2¹²⁸); magnitudes below 2⁻¹²⁶ give zero, below 2⁻⁷⁰ only `hi`.
    pub(crate) fn from_f64(x: f64) -> Option<Self> {
        let bits = x.to_bits();
        let negative = bits >> 63 != 0;
        let biased = ((bits >> 52) & 0x7ff) as i32;
        let mantissa = bits & 0x000f_ffff_ffff_ffff;
        if biased == 0x7ff {
            return None;
        }
        let e = biased - 1023;
        if e > 127 {
            return None;
        }
        if -126 > e {
            return Some(Self::ZERO);
        }
        // top 23 stored bits into hi (truncated), the next 29 into lo
        let hi_bits = (((e + 127) as u32) << 23) | (mantissa >> 29) as u32;
        let d = if -70 > e {
            // hi alone, rounded (to nearest, ties away)
            Self::from_f32(f32::from_bits(hi_bits + ((mantissa >> 28) & 1) as u32))
        } else {
            // rest·2^(e−52) = (rest·2⁻²⁹)·2^(e−23), both scalings exact
            let rest = (mantissa & 0x1fff_ffff) as u32;
            fast_two_sum(
                f32::from_bits(hi_bits),
                rest as f32 * pow2(-29) * pow2(e - 23),
            )
        };
        Some(if negative { -&d } else { d })
    }

    /// The value rounded to f32.
    // by reference, as the operators (see below): a by-value call copies the four words
    #[allow(clippy::wrong_self_convention)]
    #[cfg_attr(target_arch = "msp430", inline(never))]
    pub(crate) fn to_f32(&self) -> f32 {
        let a = by_ref(self);
        a.hi + a.lo
    }

    /// The leading f32 (for comparisons and f32 follow-up computations).
    pub(crate) fn hi(&self) -> f32 {
        self.hi
    }

    /// The trailing f32.
    pub(crate) fn lo(&self) -> f32 {
        self.lo
    }

    /// √x for x ≥ 0: the f32 root corrected by one Newton step in double length (x < 0 → NaN).
    pub(crate) fn sqrt(&self) -> Self {
        if self.hi == 0.0 {
            return Self::ZERO;
        }
        let y = crate::fmath::sqrt(self.hi);
        let r = self - &two_prod(y, y);
        fast_two_sum(y, r.hi / (2.0 * y))
    }

    /// ∛x for x > 0: f32 Newton from a bit-level guess, then one Newton step in double length.
    pub(crate) fn cbrt(&self) -> Self {
        let x = self.hi;
        // zero, negative, infinite or NaN (from the bits: NaN-safe on the MSP430)
        if x.to_bits().wrapping_sub(1) >= 0x7f7f_ffff {
            return Self::from_f32(f32::NAN);
        }
        // exponent/3 guess (within 4 %), then Newton y ← y − (y³ − x)/(3y²): quadratic
        let mut y = f32::from_bits(x.to_bits() / 3 + 709_921_077);
        for _ in 0..4 {
            y -= (y * y * y - x) / (3.0 * y * y);
        }
        let r = self - &(&two_prod(y, y) * y);
        fast_two_sum(y, r.hi / (3.0 * y * y))
    }

    /// sin x for |x| ≤ π/2: Taylor series to x²¹ in double length (truncation < 3·10⁻¹⁶).
    pub(crate) fn sin_pi_2(&self) -> Self {
        /// (−1)ᵏ/(2k+1)!, k = 0..=10.
        const C: [Df; 11] = [
            Df::from_f64_const(1.0),
            Df::from_f64_const(-1.0 / 6.0),
            Df::from_f64_const(1.0 / 120.0),
            Df::from_f64_const(-1.0 / 5040.0),
            Df::from_f64_const(1.0 / 362_880.0),
            Df::from_f64_const(-1.0 / 39_916_800.0),
            Df::from_f64_const(1.0 / 6_227_020_800.0),
            Df::from_f64_const(-1.0 / 1_307_674_368_000.0),
            Df::from_f64_const(1.0 / 355_687_428_096_000.0),
            Df::from_f64_const(-1.0 / 121_645_100_408_832_000.0),
            Df::from_f64_const(1.0 / 51_090_942_171_709_440_000.0),
        ];
        let x2 = self * self;
        let s = C.iter().rev().fold(Self::ZERO, |s, c| &(&s * &x2) + c);
        &s * self
    }
}

impl Neg for &Df {
    type Output = Df;
    fn neg(self) -> Df {
        Df {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

// The operations take their operands by reference (the operators are implemented for `&Df`
// only) and are not inlined on the MSP430: a `Df` is four 16-bit words, and an inlined
// double-length operation, or a by-value call (which copies both operands into registers or a
// temporary), costs tens of bytes of moves at each of the ~150 operations of SGP4's
// initialisation, against a few for two addresses. The results are bit for bit those of the
// same operations inlined: only the calling convention changes.

/// The operand itself. On the MSP430 an opaque use of the address, so that the optimiser keeps
/// passing the operand by reference (its argument promotion would pass both f32 by value, back
/// to the moves at every call site).
#[inline(always)]
fn by_ref(a: &Df) -> &Df {
    #[cfg(target_arch = "msp430")]
    let a = core::hint::black_box(a);
    a
}

/// Double-length sum (the accurate form: both parts summed exactly, then renormalised).
#[inline(never)]
fn add2(a: &Df, b: &Df) -> Df {
    let (a, b) = (by_ref(a), by_ref(b));
    let s = two_sum(a.hi, b.hi);
    let t = two_sum(a.lo, b.lo);
    let s = fast_two_sum(s.hi, s.lo + t.hi);
    fast_two_sum(s.hi, s.lo + t.lo)
}

/// `a − b` as `a + (−b)`.
#[cfg_attr(target_arch = "msp430", inline(never))]
fn sub2(a: &Df, b: &Df) -> Df {
    add2(a, &-by_ref(b))
}

/// Double-length product (Dekker's `mul2`).
#[inline(never)]
fn mul2(a: &Df, b: &Df) -> Df {
    let (a, b) = (by_ref(a), by_ref(b));
    let p = two_prod(a.hi, b.hi);
    fast_two_sum(p.hi, p.lo + (a.hi * b.lo + a.lo * b.hi))
}

/// Double-length quotient: the f32 quotient and two corrections from the exact remainder.
#[inline(never)]
fn div2(a: &Df, b: &Df) -> Df {
    let (a, b) = (by_ref(a), by_ref(b));
    let q1 = a.hi / b.hi;
    let r = a - &(b * q1);
    let q2 = r.hi / b.hi;
    let r = &r - &(b * q2);
    let q3 = r.hi / b.hi;
    &fast_two_sum(q1, q2) + q3
}

macro_rules! operators {
    ($tr:ident, $f:ident, $kernel:ident, $with_f32:ident, $f32_with:ident) => {
        impl $tr<&Df> for &Df {
            type Output = Df;
            #[inline(always)]
            fn $f(self, b: &Df) -> Df {
                $kernel(self, b)
            }
        }
        /// `Df op f32`, the f32 as a `Df` with a zero tail.
        #[cfg_attr(target_arch = "msp430", inline(never))]
        fn $with_f32(a: &Df, b: f32) -> Df {
            $kernel(a, &Df::from_f32(b))
        }
        /// `f32 op Df`, the f32 as a `Df` with a zero tail.
        #[cfg_attr(target_arch = "msp430", inline(never))]
        fn $f32_with(a: f32, b: &Df) -> Df {
            $kernel(&Df::from_f32(a), b)
        }
        impl $tr<f32> for &Df {
            type Output = Df;
            #[inline(always)]
            fn $f(self, b: f32) -> Df {
                $with_f32(self, b)
            }
        }
        impl $tr<&Df> for f32 {
            type Output = Df;
            #[inline(always)]
            fn $f(self, b: &Df) -> Df {
                $f32_with(self, b)
            }
        }
    };
}
operators!(Add, add, add2, add_f32, f32_add);
operators!(Sub, sub, sub2, sub_f32, f32_sub);
operators!(Mul, mul, mul2, mul_f32, f32_mul);
operators!(Div, div, div2, div_f32, f32_div);

#[cfg(test)]
mod tests {
    use super::*;

    fn val(d: Df) -> f64 {
        f64::from(d.hi) + f64::from(d.lo)
    }

    fn rel(d: Df, x: f64) -> f64 {
        ((val(d) - x) / x).abs()
    }

    #[test]
    fn from_f64_keeps_48_bits() {
        for &x in &[
            15.729_257_21,
            -0.000_082_95,
            0.185_966_7,
            98.703_6,
            1.0e-30,
            -2.5e-20,
            3.0e37,
            -1.0,
            0.0,
        ] {
            let d = Df::from_f64(x).unwrap();
            let bound = if x.abs() < 1e-21 {
                2f64.powi(-24)
            } else {
                2f64.powi(-47)
            };
            assert!(x == 0.0 || rel(d, x) < bound, "{x}");
            assert_eq!(d.to_f32(), x as f32, "{x}");
        }
        assert!(Df::from_f64(f64::NAN).is_none());
        assert!(Df::from_f64(f64::INFINITY).is_none());
        assert!(Df::from_f64(1.0e39).is_none());
        assert_eq!(Df::from_f64(1.0e-39).unwrap(), Df::ZERO);
    }

    #[test]
    fn arithmetic_to_2_pow_minus_44() {
        let xs = [
            0.074_366_916_133_173_42,
            0.062_002_077_468_705_51,
            1.128_436_148_894_23,
            0.999_966_3,
            6378.135,
            1.0e-3,
            0.185_966_7,
            3.0,
        ];
        let mut worst = 0.0f64;
        for &a in &xs {
            let da = Df::from_f64(a).unwrap();
            let a = val(da);
            worst = worst.max(rel(da.sqrt(), a.sqrt()));
            worst = worst.max(rel(da.cbrt(), a.cbrt()));
            for &b in &xs {
                let db = Df::from_f64(b).unwrap();
                let b = val(db);
                worst = worst.max(rel(&da + &db, a + b));
                worst =
                    worst.max(rel(&da - &db, a - b).min(((val(&da - &db) - (a - b)) / a).abs()));
                worst = worst.max(rel(&da * &db, a * b));
                worst = worst.max(rel(&da / &db, a / b));
            }
        }
        println!("double-f32 worst relative error {worst:e}");
        assert!(worst < 2f64.powi(-44), "{worst:e}");
    }

    #[test]
    fn sine_to_1e_14() {
        let mut worst = 0.0f64;
        for k in -200..=200 {
            let x = f64::from(k) / 200.0 * core::f64::consts::FRAC_PI_2;
            let d = Df::from_f64(x).unwrap();
            worst = worst.max((val(d.sin_pi_2()) - val(d).sin()).abs());
        }
        println!("double-f32 sin worst absolute error {worst:e}");
        assert!(worst < 1e-14, "{worst:e}");
    }
}
