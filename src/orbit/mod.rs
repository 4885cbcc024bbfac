//! Orbit propagation: SGP4 (near-Earth) and the two-body Kepler propagator.
//!
//! Both propagators take the time since the element set's epoch as a [`TimeSpan`] (exact integer
//! seconds and nanoseconds) and return a [`TemeState`]. Their secular angles grow by hundreds of
//! radians a week, more than f32 can hold to the metre, so they are kept as a `Phase`: a
//! fixed-point fraction of a turn that is advanced exactly by the whole time units and in f32
//! only by the sub-unit remainder (see `Phase` for the numbers).

use crate::linalg::Vec3;
use crate::time::{TimeSpan, Wide};

mod dfloat;
pub mod kepler;
pub mod sgp4;

use dfloat::Df;

/// Position and velocity in the TEME frame of date (km, km/s).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct TemeState {
    /// Position, TEME of date, km.
    pub r_teme_km: Vec3,
    /// Velocity, TEME of date, km/s.
    pub v_teme_kmps: Vec3,
}

#[cfg(feature = "defmt")]
impl defmt::Format for TemeState {
    fn format(&self, f: defmt::Formatter) {
        defmt::write!(
            f,
            "r=({},{},{}) km v=({},{},{}) km/s",
            self.r_teme_km.x,
            self.r_teme_km.y,
            self.r_teme_km.z,
            self.v_teme_kmps.x,
            self.v_teme_kmps.y,
            self.v_teme_kmps.z
        )
    }
}

/// Fractional bits of a [`Phase`]: one turn is `2^PHASE_BITS`.
const PHASE_BITS: u32 = 48;
/// `2^-PHASE_BITS` as f32 (exact).
const PHASE_ULP_F32: f32 = 1.0 / (1u64 << PHASE_BITS) as f32;
/// `2^PHASE_BITS` as f32 (exact).
const PHASE_ONE_F32: f32 = (1u64 << PHASE_BITS) as f32;
/// `2^PHASE_BITS` as f64 (exact).
const PHASE_ONE_F64: f64 = (1u64 << PHASE_BITS) as f64;

/// A secular angle `θ(t) = θ₀ + θ̇·t`, kept so that it loses no bits however large `θ̇·t` grows.
///
/// `θ₀` and `θ̇` (per time unit: minute for SGP4, second for Kepler) are stored in turns as
/// 48-bit fixed-point fractions, reduced modulo one turn. For a time `t = w + f` with `w` whole
/// units and `0 ≤ f < 1`, the fixed-point part `θ₀ + θ̇·w` is computed with wrapping 64-bit
/// integer arithmetic, which is exact modulo one turn for any `w` (a "phase accumulator"); only
/// `θ̇·f`, less than one unit's worth of angle, is an f32 product. The result is then a single
/// f32 rounding of a value in −½..½ turn: at most 2⁻²⁵ turn = 1.9e-7 rad, plus the 2⁻⁴⁹ turn/unit
/// quantisation of the rate (3.5e-7 rad after 10⁷ units). Compare a plain f32 `θ₀ + θ̇·t`: at
/// 300 rad the spacing of f32 values is 3e-5 rad, 200 m along a low orbit.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(crate) struct Phase {
    /// `θ₀`, turns × 2^48, in −2^47..2^47.
    at_epoch: i64,
    /// `θ̇` modulo one turn per unit, turns × 2^48.
    rate_fx: i64,
    /// `θ̇` in turns per unit (not reduced), for the sub-unit remainder.
    rate_turns: f32,
}

impl Phase {
    /// The zero phase (a placeholder before the parts are read).
    pub(crate) const ZERO: Self = Self {
        at_epoch: 0,
        rate_fx: 0,
        rate_turns: 0.0,
    };

    /// A phase from its epoch value (rad) and rate (rad per time unit), computed in f64 at
    /// initialisation. Non-finite inputs give a zero phase; callers validate them first.
    pub(crate) fn new(at_epoch_rad: f64, rate_rad_per_unit: f64) -> Self {
        let turns0 = at_epoch_rad / core::f64::consts::TAU;
        let rate = rate_rad_per_unit / core::f64::consts::TAU;
        Self {
            at_epoch: libm::round((turns0 - libm::round(turns0)) * PHASE_ONE_F64) as i64,
            rate_fx: libm::round((rate - libm::round(rate)) * PHASE_ONE_F64) as i64,
            rate_turns: rate as f32,
        }
    }

    /// A phase from its epoch value (turns) and rate (turns per time unit) in double-f32,
    /// with f32 and integer operations only (no f64 arithmetic): each part is reduced modulo
    /// one turn and scaled by 2⁴⁸ exactly, then rounded to an integer (a 2⁻⁴⁹-turn error).
    pub(crate) fn from_turns(at_epoch_turns: &Df, rate_turns_per_unit: &Df) -> Self {
        Self {
            at_epoch: fixed_turns(at_epoch_turns),
            rate_fx: fixed_turns(rate_turns_per_unit),
            rate_turns: rate_turns_per_unit.to_f32(),
        }
    }

    /// `θ(w + f)` in turns, about −½..½ (the remainder term may add up to `|θ̇|`).
    pub(crate) fn turns(&self, whole: i32, frac: f32) -> f32 {
        // θ₀ + θ̇·w modulo 2⁶⁴ in 32-bit words ([`Wide`]: no 64-bit multiply on the MSP430)
        let product = Wide::from_u64(self.rate_fx as u64).wrapping_mul_i32(whole);
        let p = Wide::from_u64(self.at_epoch as u64)
            .wrapping_add(product)
            .to_u64() as i64;
        // sign-extend bit 47: the phase modulo one turn, in −½..½ turn
        let reduced = p
            .wrapping_shl(64 - PHASE_BITS)
            .wrapping_shr(64 - PHASE_BITS);
        i48_to_f32(reduced) * PHASE_ULP_F32 + self.rate_turns * frac
    }

    /// `θ(w + f)` in radians, about −π..π.
    pub(crate) fn radians(&self, whole: i32, frac: f32) -> f32 {
        self.turns(whole, frac) * core::f32::consts::TAU
    }

    /// The stored parts `(θ₀ · 2⁴⁸, θ̇ mod 1 · 2⁴⁸, θ̇)`, for an uplink of the initialised elements.
    pub(crate) fn raw(&self) -> (i64, i64, f32) {
        (self.at_epoch, self.rate_fx, self.rate_turns)
    }

    /// The parts of [`Phase::raw`] to be written in place, for an uplink's words read into a
    /// phase (which checks that they are those an initialisation can make: both fixed-point
    /// values within ±2⁴⁷, half a turn, and the rate finite).
    pub(crate) fn raw_mut(&mut self) -> (&mut i64, &mut i64, &mut f32) {
        (&mut self.at_epoch, &mut self.rate_fx, &mut self.rate_turns)
    }
}

/// `x as f32` for |x| ≤ 2⁴⁷, without the `i64` → f32 helper (`__floatdisf`, 990 B on the
/// MSP430): `x = a·2²⁴ + b` with `a` and `0 ≤ b < 2²⁴` exact in f32, and their f32 sum is the
/// exact value rounded once to nearest-even, the same f32 as the conversion.
fn i48_to_f32(x: i64) -> f32 {
    let a = (x >> 24) as i32;
    let b = (x & 0xff_ffff) as i32;
    a as f32 * 16_777_216.0 + b as f32
}

/// A double-f32 number of turns as a 48-bit fixed-point fraction, modulo one turn, in
/// −2⁴⁷..2⁴⁷ (non-finite input gives 0).
fn fixed_turns(x: &Df) -> i64 {
    fixed_turns_f32(x.hi())
        .wrapping_add(fixed_turns_f32(x.lo()))
        .wrapping_shl(64 - PHASE_BITS)
        .wrapping_shr(64 - PHASE_BITS)
}

/// An f32 number of turns, modulo one turn, times 2⁴⁸, rounded (non-finite input gives 0).
/// Not inlined on the MSP430 (called for both parts of a double-f32: half the code).
#[cfg_attr(target_arch = "msp430", inline(never))]
fn fixed_turns_f32(v: f32) -> i64 {
    // not finite (from the bits: NaN-safe on the MSP430)
    if v.to_bits() & 0x7f80_0000 == 0x7f80_0000 {
        return 0;
    }
    // v − round(v) is exact (Sterbenz); the 2⁴⁸ scaling too; beyond 2²³ it is an integer
    let r = v - crate::fmath::floor(v + 0.5);
    let s = r * PHASE_ONE_F32;
    integral_f32_to_i64(if crate::fmath::abs(s) >= 8_388_608.0 {
        s
    } else {
        crate::fmath::floor(s + 0.5)
    })
}

/// `x as i64` for an integer-valued f32 with |x| < 2⁵⁴ (exact), without the f32 → `i64`
/// helper (`__fixsfdi`, 492 B on the MSP430, used by nothing else in the flight image):
/// `x = h·2²⁴ + l` with `h = ⌊x·2⁻²⁴⌋` and `0 ≤ l < 2²⁴`, each step exact in f32, and both
/// parts small enough for `i32`.
fn integral_f32_to_i64(x: f32) -> i64 {
    const TWO_24: f32 = 16_777_216.0;
    let h = crate::fmath::floor(x * (1.0 / TWO_24));
    let l = x - h * TWO_24;
    (i64::from(h as i32) << 24) + i64::from(l as i32)
}

/// A time span as `(whole, frac)`: whole units (floor) and the remainder `0 ≤ frac < 1` in f32,
/// for a unit of `unit_seconds` seconds. Spans beyond ±2³¹ units saturate.
pub(crate) fn split_span(span: TimeSpan, unit_seconds: i32) -> (i32, f32) {
    let secs = span.whole_seconds();
    let whole = secs.div_euclid(unit_seconds);
    let rem = secs.rem_euclid(unit_seconds);
    let frac = (rem as f32 + span.nanos() as f32 * 1e-9) / unit_seconds as f32;
    (whole, frac)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn phase_is_exact_over_long_spans() {
        // 15.5 rev/day for 10^6 minutes: f64 reference, reduced
        let rate = 15.5 * core::f64::consts::TAU / 1440.0;
        let p = Phase::new(1.0, rate);
        for &w in &[0i32, 1, 4320, 10_080, 1_000_000, -1_000_000] {
            let exact = (1.0 + rate * (f64::from(w) + 0.25)) / core::f64::consts::TAU;
            let exact = exact - libm::round(exact);
            let got = f64::from(p.turns(w, 0.25));
            let d = got - exact;
            let d = d - libm::round(d);
            assert!(d.abs() < 1e-7, "w={w}: {got} vs {exact}");
        }
    }

    #[test]
    fn phase_from_double_f32_turns_matches_f64() {
        // M₀ = 19.3264°, Ṁ of 15.5 rev/day, and a negative, larger-than-a-turn case
        for &(deg, rev_day) in &[
            (19.3264, 15.5),
            (-725.25, 10.824_191_574),
            (359.9999, 0.001),
        ] {
            let tau = core::f64::consts::TAU;
            let rate = rev_day * tau / 1440.0;
            let a = Phase::new(deg / 360.0 * tau, rate);
            let turns = Df::from_f64(deg / 360.0).unwrap();
            let b = Phase::from_turns(&turns, &Df::from_f64(rev_day / 1440.0).unwrap());
            assert!((a.at_epoch - b.at_epoch).abs() <= 2, "{deg}: {a:?} {b:?}");
            assert!((a.rate_fx - b.rate_fx).abs() <= 2, "{rev_day}: {a:?} {b:?}");
            assert_eq!(a.rate_turns, b.rate_turns);
        }
    }

    #[test]
    fn i48_to_f32_is_the_conversion() {
        // ties (odd and even), carries into the exponent, both signs, the ends of the range
        let mut cases = vec![
            0i64,
            1,
            -1,
            (1 << 47) - 1,
            -(1 << 47),
            1 << 24,
            (1 << 25) + 1,
        ];
        for k in 24..47 {
            for d in [-3i64, -2, -1, 0, 1, 2, 3] {
                let base = 1i64 << k;
                let half = 1i64 << (k - 24);
                cases.extend([
                    base + d,
                    base + half + d,
                    base + 3 * half + d,
                    -(base + half + d),
                ]);
            }
        }
        let mut x = 0x1234_5678_9abc_i64;
        for _ in 0..100_000 {
            // xorshift, folded into −2⁴⁷..2⁴⁷
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            cases.push(x.wrapping_shl(16).wrapping_shr(16));
        }
        for &c in &cases {
            assert_eq!(i48_to_f32(c).to_bits(), (c as f32).to_bits(), "{c}");
        }
    }

    #[test]
    fn integral_f32_to_i64_is_the_conversion() {
        let mut cases: Vec<f32> = (-70_000..70_000).map(|k| k as f32).collect();
        for k in 0..54 {
            let p = (1u64 << k) as f32;
            for m in [1.0f32, 1.5, 1.75, 1.999_999_9] {
                cases.extend([p * m, -p * m].iter().map(|&v| v.trunc()));
            }
        }
        let mut x = 0x2545_f491u32;
        for _ in 0..100_000 {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            // random integer-valued f32 below 2^54
            let v = f32::from_bits((x & 0x8000_0000) | ((x % (54 << 23)) + (127 << 23)));
            cases.push(v.trunc());
        }
        cases.push(-0.0);
        for &c in &cases {
            assert_eq!(integral_f32_to_i64(c), c as i64, "{c:e}");
        }
    }

    #[test]
    fn split_span_floors() {
        let s = TimeSpan::new(-90, 500_000_000); // −89.5 s
        let (w, f) = split_span(s, 60);
        assert_eq!(w, -2);
        assert!((f - 30.5 / 60.0).abs() < 1e-7);
    }
}
