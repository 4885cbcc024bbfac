//! The precise Sun: apparent geocentric direction of date in TEME, and distance.
//!
//! # Method
//! 1. Geometric heliocentric ecliptic longitude `L` and radius `R` of the Earth from VSOP87D
//!    (P. Bretagnon, G. Francou, A&A 202, 309, 1988) as abridged by J. Meeus, *Astronomical
//!    Algorithms*, 2nd ed., ch. 25 "higher accuracy" and appendix III
//!    (`tests/data/vsop87_meeus_earth.csv`), regrouped by `tools/sun_precise_gen.py` (which
//!    writes the constants below) into three parts that cost little on a 16-bit core:
//!    - the **equation of the centre**, the terms of frequency `M'` and `2M'` (`M'` the argument
//!      of the first `L0` term) with every power of τ, as polynomials in τ multiplying the precise
//!      `cos kM'`, `sin kM'` (one table sine-cosine and the double-angle formulas);
//!    - the **slow terms** (periods over 200 years) and the constants of `L2…L5`, `R1…R4`: one
//!      least-squares polynomial in τ over 1950–2100 (error ≤ 2e-8 rad);
//!    - the **planetary and lunar terms** of amplitude ≥ 200e-8 rad in `L` (0.41″) or ≥ 300e-8 AU
//!      in `R`, each argument an integer combination of six fundamental arguments (`M'`, the mean
//!      longitudes of Venus, Mars, Jupiter and Saturn, the Moon's elongation `D`) in 2^-16 turn,
//!      its cosine read from a 1 024-point table (no interpolation: ≤ 3.1e-3 of the amplitude).
//!
//!    The latitude `B` (≤ 0.6″) and the terms without such a combination are dropped.
//! 2. Geocentric Sun: `λ = L + 180°`, `β = 0`; the FK5 correction −0.09033″ (Meeus eq. 25.9).
//! 3. Nutation (IAU 1980, Seidelmann 1982) truncated to the five terms that move the Sun by
//!    more than 0.1″ (arguments Ω, 2L☉, 2L☾, 2Ω, l′, from the same fundamental arguments; the
//!    `T` rates dropped). Over 1950–2100 it is within 0.29″ in Δψ and 0.11″ in Δε of the 40-term
//!    [`crate::frames::nutation`] used by TEME → J2000 (unit test
//!    `truncated_nutation_against_frames_nutation`); the direction moves by less than that (Δψ
//!    shifts both the longitude and the TEME equinox), and the whole-model comparison below
//!    includes it.
//! 4. Aberration (with the light time of the Sun's apparent motion): `−20.4898″ / R`
//!    (Meeus eq. 25.10); apparent longitude `λ_app = λ + Δψ − 20.4898″/R`.
//! 5. True equator of date with `ε = ε̄ + Δε` (ε̄ IAU 1976 to first order in T); then TEME (true
//!    equator, **mean** equinox): the right ascension decreases by the equation of the equinoxes
//!    `Δψ·cos ε̄`.
//!
//! # Symbols
//! | name | symbol | meaning |
//! |---|---|---|
//! | `n`, `f` | | whole days and fraction since J2000.0 (2000-01-01 12:00 TT) |
//! | `tau` | τ | Julian millennia of TT since J2000.0 |
//! | `t` | T | Julian centuries of TT since J2000.0 |
//! | `lon_mean` | L + 180° (L0, L1 constants) | geometric mean longitude of the Sun, turns |
//! | `m` | M' | argument of VSOP87's first `L0` term (mean anomaly − 90°), turns |
//! | `Fund` | M', V, Ma, J, S, D, L☉, Ω | fundamental arguments, 2^-16 turn |
//! | `r_au` | R | Earth–Sun distance (AU) |
//! | `dpsi`, `deps` | Δψ, Δε | nutation in longitude and obliquity |
//! | `eqeq` | | equation of the equinoxes `Δψ cos ε̄` |
//!
//! # Precision and cost
//! The mean longitude is reduced modulo one turn in exact fixed point from the whole day count
//! (`LinearAngle`); the longitude is kept in turns, so its sine and cosine need no floating
//! range reduction (`sincos_turns`: table point + second-order correction, 5e-9 + f32
//! rounding). No f64, no division but the aberration's, 2 table sine-cosines; the 36 cosines of
//! the periodic and nutation terms are Q14 table values times 16-bit amplitudes summed in i32
//! (exact; one conversion to f32 per sum; the periodic terms are a table walked by one loop, for
//! flash), and the fundamental arguments are exact 32-bit fixed point. About 47 400 MSP430 cycles
//! without hardware multiplier (`docs/firmware.md`, "MSP430 firmware and cycle budget").
//!
//! # Range and measured accuracy
//! Years 1950–2100 in TT ([`sun_tt`]); from UTC ([`sun`]) 1972–2100, the leap-second era. Other
//! years give [`SunError`]. Against the apparent Sun of JPL DE421 in TEME of date
//! (`tests/data/sun/sun_de421.csv`, 400 instants 1990–2050, UTC input): see `docs/accuracy.md`,
//! "Sun direction" table (`cargo test --test sun -- --nocapture`, which holds 15″ and 2e-5 AU on
//! every row); over the whole range 1950–2100 against the full abridged series of Meeus in f64
//! (test `precise_truncation_over_1950_2100`).

use super::{year_of_day, LinearAngle, Sun, SunError};
use crate::linalg::Vec3;
use crate::time::{days_from_civil, Epoch, Tt, Utc};

/// One arcsecond in radians.
const ARCSEC: f32 = (core::f64::consts::PI / 648_000.0) as f32;
/// 0.0001″ in radians (the unit of the IAU 1980 nutation table).
/// 0.001″ × 2^-14 in radians: the unit of the nutation sums (amplitude in 0.001″ × Q14 cosine).
const NUT_SUM_UNIT: f32 = (core::f64::consts::PI / 648_000.0 * 1e-3 / 16_384.0) as f32;
/// Units of the integer amplitudes of the periodic terms: 2e-9 rad (L), 1e-9 AU (R).
const L_UNIT: f64 = 2e-9;
const R_UNIT: f64 = 1e-9;

/// First and last TT day (since 2000-01-01) of the model's range, 1950-01-01 and 2100-12-31.
const FIRST_DAY: i32 = days_from_civil(1950, 1, 1);
const LAST_DAY: i32 = days_from_civil(2100, 12, 31);

/// Mean longitude of the Sun: the constant of `L0` and the linear term of `L1`, plus 180°.
const MEAN_LONGITUDE: LinearAngle = LinearAngle::from_radians_per_millennium(
    1.753_470_46 + core::f64::consts::PI,
    6_283.319_667_47,
);

/// `M' = lon_mean + M_OFFSET + M_RATE·τ` (turns): VSOP87's first `L0` argument
/// 4.669 256 8 + 6 283.075 85 τ rad minus the mean longitude.
const M_OFFSET: f32 =
    ((4.669_256_8 - 1.753_470_46 - core::f64::consts::PI) / core::f64::consts::TAU) as f32;
const M_RATE: f32 = ((6_283.075_85 - 6_283.319_667_47) / core::f64::consts::TAU) as f32;

/// A fundamental argument `phase + rate·days` in fixed point: phase at J2000.0 in 2^-32 turn,
/// rate in 2^-32 turn per day (wrapping: negative rates in two's complement) and in 2^-16 turn
/// per day (for the fraction of the day).
#[derive(Copy, Clone)]
struct Fundamental {
    phase_q32: u32,
    rate_q32: u32,
    rate_q16: i16,
}

/// `x.floor()` for |x| < 2^53 (not in `core`).
const fn floor_f64(x: f64) -> f64 {
    let w = x as i64 as f64;
    if w > x {
        w - 1.0
    } else {
        w
    }
}

const fn fundamental(phase_rad: f64, rate_rad_per_millennium: f64) -> Fundamental {
    let turns = phase_rad / core::f64::consts::TAU;
    let rate = rate_rad_per_millennium / core::f64::consts::TAU / 365_250.0;
    let q32 = 4_294_967_296.0;
    Fundamental {
        phase_q32: ((turns - floor_f64(turns)) * q32) as u32,
        rate_q32: ((rate - floor_f64(rate)) * q32) as u32,
        rate_q16: (rate * 65_536.0) as i16,
    }
}

/// Mean longitudes of VSOP87 (J. L. Simon et al., A&A 282, 663, 1994, as used by VSOP87).
const VENUS: Fundamental = fundamental(3.176_146_69, 10_213.285_546_2);
const MARS: Fundamental = fundamental(6.203_481_42, 3_340.612_426_7);
const JUPITER: Fundamental = fundamental(0.599_546_91, 529.690_965_1);
const SATURN: Fundamental = fundamental(0.874_016_75, 213.299_095_4);
/// The Moon's mean elongation D (IAU 1980: 297.850 363 06° + 1 602 961 601.2090″/century).
const ELONGATION: Fundamental = fundamental(5.198_466_741, 77_713.771_468_1);
/// Longitude of the Moon's ascending node Ω (IAU 1980: 125.044 522 22° − 1 934.136 261°/century).
const NODE: Fundamental = fundamental(
    125.044_522_22 * core::f64::consts::PI / 180.0,
    -1_934.136_261 * 10.0 * core::f64::consts::PI / 180.0,
);

/// Nutation in longitude (IAU 1980, Seidelmann 1982 table; the `T` rates, ≤ 0.018″ by 2100,
/// dropped), 0.0001″: coefficients of sin Ω, sin 2L☉, sin 2L☾, sin 2Ω, sin l′.
const NUTATION_DPSI: [f32; 5] = [-171_996.0, -13_187.0, -2_274.0, 2_062.0, 1_426.0];
/// [`NUTATION_DPSI`] in 0.001″ (rounded), for the integer sum.
const DPSI_MAS: [i16; 5] = mas(NUTATION_DPSI);
/// Nutation in obliquity, 0.0001″: coefficients of cos Ω, cos 2L☉, cos 2L☾, cos 2Ω.
const NUTATION_DEPS: [f32; 4] = [92_025.0, 5_736.0, 977.0, -895.0];
/// [`NUTATION_DEPS`] in 0.001″ (rounded).
const DEPS_MAS: [i16; 4] = mas(NUTATION_DEPS);

/// Table coefficients in 0.0001″ to i16 in 0.001″, rounded half away from zero.
#[allow(clippy::indexing_slicing)] // const evaluation: an index out of range is a build error
const fn mas<const N: usize>(c: [f32; N]) -> [i16; N] {
    let mut out = [0; N];
    let mut i = 0;
    while N > i {
        let x = c[i] / 10.0;
        out[i] = if !(x >= 0.0) {
            (x - 0.5) as i16
        } else {
            (x + 0.5) as i16
        };
        i += 1;
    }
    out
}

/// Mean obliquity at J2000 (IAU 1976: 84 381.448″) and its rate (−46.8150″ per century).
const EPS0_RAD: f64 = 84_381.448 * core::f64::consts::PI / 648_000.0;
const SIN_EPS0: f32 = sin_f64(EPS0_RAD) as f32;
const COS_EPS0: f32 = cos_f64(EPS0_RAD) as f32;
const EPS_RATE: f32 = -46.815_0 * ARCSEC;

// BEGIN GENERATED by tools/sun_precise_gen.py from tests/data/vsop87_meeus_earth.csv: do not edit.
/// Slow part of `L` (periods > 200 years, and the constants of the powers of tau above 1):
/// coefficients of tau^0..tau^5, rad; fit error 2.0e-08 rad over 1950-2100.
const SLOW_L: [f32; 6] = [
    -3.9064103e-05,
    -2.632257e-04,
    2.0723792e-03,
    2.3986697e-02,
    -8.903473e-02,
    -3.4946233e-01,
];
/// Slow part of `R` (periods > 200 years, and the constants of the powers of tau above 1):
/// coefficients of tau^0..tau^1, AU; fit error 3.4e-10 AU over 1950-2100.
const SLOW_R: [f32; 2] = [1.0001398e+00, -7.0261194e-06];
/// `L`, terms of frequency 1x6283.07585 rad/millennium: coefficient of cos(1M'), rad, tau^0..
const L1_COS: [f32; 3] = [3.341656e-02, -8.4065134e-04, -7.830673e-05];
/// `L`, terms of frequency 1x6283.07585 rad/millennium: coefficient of sin(1M'), rad, tau^0..
const L1_SIN: [f32; 3] = [0.0e+00, 1.8813125e-03, -3.8365295e-05];
/// `L`, terms of frequency 2x6283.07585 rad/millennium: coefficient of cos(2M'), rad, tau^0..
const L2_COS: [f32; 2] = [8.590769e-09, 3.928621e-05];
/// `L`, terms of frequency 2x6283.07585 rad/millennium: coefficient of sin(2M'), rad, tau^0..
const L2_SIN: [f32; 2] = [-3.4894e-04, 1.7554901e-05];
/// `R`, terms of frequency 1x6283.07585 rad/millennium: coefficient of cos(1M'), AU, tau^0..
const R1_COS: [f32; 2] = [5.0568662e-08, -9.405819e-04];
/// `R`, terms of frequency 1x6283.07585 rad/millennium: coefficient of sin(1M'), AU, tau^0..
const R1_SIN: [f32; 2] = [1.6707e-02, -4.2023454e-04];
/// `R`, terms of frequency 2x6283.07585 rad/millennium: coefficient of cos(2M'), AU, tau^0..
const R2_COS: [f32; 2] = [1.3956e-04, -7.019631e-06];
/// `R`, terms of frequency 2x6283.07585 rad/millennium: coefficient of sin(2M'), AU, tau^0..
const R2_SIN: [f32; 2] = [1.0926546e-08, 1.5713335e-05];
// Periodic terms: multipliers of (M', V, Ma, J, S, D); L: amplitude (rad), phase (2^-16 turn); R likewise (AU).
macro_rules! periodic_terms {
    ($t:ident) => {
        $t!([1, 0, 0, -1, 0, 0], 3.497e-05, 51709, 1.628e-05, 35332);
        $t!([0, 0, 0, 0, 0, 1], 3.136e-05, 49152, 3.084e-05, 0);
        $t!([-2, 2, 0, 0, 0, 0], 2.676e-05, 11694, 1.576e-05, 60842);
        $t!([-1, 1, 0, 0, 0, 0], 2.343e-05, 14030, 5.42e-06, 63178);
        $t!([2, 0, 0, -2, 0, 0], 1.324e-05, 53919, 9.25e-06, 37516);
        $t!([0, 0, 0, 1, 0, 0], 1.273e-05, 14994, 0.0e+00, 0);
        $t!([-3, 2, 0, 0, 0, 0], 1.199e-05, 25887, 0.0e+00, 0);
        $t!([2, 0, -2, 0, 0, 0], 9.9e-06, 21051, 4.72e-06, 4655);
        $t!([-1, 0, 2, 0, 0, 0], 8.57e-06, 21419, 0.0e+00, 0);
        $t!([1, 0, 0, -2, 0, 0], 7.8e-06, 41638, 3.29e-06, 25344);
        $t!([-4, 3, 0, 0, 0, 0], 7.53e-06, 56307, 3.46e-06, 39942);
        $t!([3, 0, 0, 0, 0, 0], 5.05e-06, 32768, 0.0e+00, 0);
        $t!([5, -3, 0, 0, 0, 0], 4.92e-06, 30806, 0.0e+00, 0);
        $t!([-3, 3, 0, 0, 0, 0], 3.17e-06, 42192, 0.0e+00, 0);
        $t!([-2, 0, 4, 0, 0, 0], 2.84e-06, 55001, 0.0e+00, 0);
        $t!([2, 0, 0, -3, 0, 0], 2.71e-06, 55714, 0.0e+00, 0);
        $t!([3, 0, -4, 0, 0, 0], 2.43e-06, 50775, 0.0e+00, 0);
        $t!([2, 0, -3, 0, 0, 0], 2.06e-06, 15766, 0.0e+00, 0);
        $t!([1, 0, 0, 0, -1, 0], 2.02e-06, 51588, 0.0e+00, 0);
    };
}
// END GENERATED

/// A planetary or lunar term of `L` and `R`: its argument is `k₁·F[i₁] + k₂·F[i₂]` (`args`) over
/// the six fundamental arguments F = (M', V, Ma, J, S, D), plus a phase; amplitudes in
/// [`L_UNIT`] and [`R_UNIT`] (`r_amp` 0: no `R` term), phases in 2^-16 turn. A table walked by one
/// loop: as 19 inlined terms it was ≈ 2 KB of MSP430 code.
#[derive(Copy, Clone)]
struct Term {
    args: [(u8, i8); 2],
    l_amp: i16,
    l_phase: u16,
    r_amp: i16,
    r_phase: u16,
}

/// A [`Term`] from the generated multipliers of (M', V, Ma, J, S, D), amplitudes (rad, AU) and
/// phases (2^-16 turn); a term with more than two non-zero multipliers is a build error.
#[allow(clippy::indexing_slicing)] // const evaluation: an index out of range is a build error
const fn term(k: [i32; 6], la: f64, lp: u16, ra: f64, rp: u16) -> Term {
    let mut args = [(0, 0); 2];
    let mut n = 0;
    let mut i = 0;
    while 6 > i {
        if k[i] != 0 {
            args[n] = (i as u8, k[i] as i8);
            n += 1;
        }
        i += 1;
    }
    Term {
        args,
        l_amp: (la / L_UNIT + 0.5) as i16,
        l_phase: lp,
        r_amp: (ra / R_UNIT + 0.5) as i16,
        r_phase: rp,
    }
}

/// The number of generated periodic terms.
const TERM_COUNT: usize = {
    let mut n = 0;
    macro_rules! count {
        ($($x:tt)*) => {
            n += 1;
        };
    }
    periodic_terms!(count);
    n
};

/// The generated periodic terms as a table.
#[allow(clippy::indexing_slicing)] // const evaluation: an index out of range is a build error
#[allow(unused_assignments)] // the last entry's index increment
static TERMS: [Term; TERM_COUNT] = {
    let mut t = [term([0; 6], 0.0, 0, 0.0, 0); TERM_COUNT];
    let mut i = 0;
    macro_rules! entry {
        ($k:tt, $la:literal, $lp:literal, $ra:literal, $rp:literal) => {
            t[i] = term($k, $la, $lp, $ra, $rp);
            i += 1;
        };
    }
    periodic_terms!(entry);
    t
};

/// Taylor series of cos for |x| ≤ π/2, f64 (error < 1e-20), for the constant tables.
const fn cos_f64(x: f64) -> f64 {
    let x2 = x * x;
    let mut term = 1.0;
    let mut sum = 1.0;
    let mut k = 1.0;
    while !(k >= 24.0) {
        term = -term * x2 / (k * (k + 1.0));
        sum += term;
        k += 2.0;
    }
    sum
}

/// Taylor series of sin for |x| ≤ π/2, f64.
const fn sin_f64(x: f64) -> f64 {
    let x2 = x * x;
    let mut term = x;
    let mut sum = x;
    let mut k = 2.0;
    while !(k >= 25.0) {
        term = -term * x2 / (k * (k + 1.0));
        sum += term;
        k += 2.0;
    }
    sum
}

/// `cos(2π i / 1024)` for i = 0..=256 (a quarter turn), in 2^-30 (Q30).
#[allow(clippy::indexing_slicing)] // const evaluation: an index out of range is a build error
const fn quarter_cos_table() -> [i32; 257] {
    let mut t = [0; 257];
    let mut i = 0;
    while 257 > i {
        let c = cos_f64(i as f64 * (core::f64::consts::FRAC_PI_2 / 256.0));
        t[i] = (c * 1_073_741_824.0 + 0.5) as i32;
        i += 1;
    }
    t
}

/// `cos(2π i / 1024)`, i = 0..=256, Q30 (1 KB of flash).
static QUARTER_COS: [i32; 257] = quarter_cos_table();

/// `(sin, cos)` of `i` 1024ths of a turn (`i` taken modulo 1024), Q30.
fn table_sin_cos(i: u16) -> (i32, i32) {
    let k = usize::from(i & 0xFF);
    let a = QUARTER_COS.get(k).copied().unwrap_or(1 << 30);
    let b = QUARTER_COS.get(256 - k).copied().unwrap_or(0);
    match (i >> 8) & 3 {
        0 => (b, a),
        1 => (a, -b),
        2 => (-b, -a),
        _ => (-a, b),
    }
}

/// Cosine of an angle in 2^-16 turn, Q14, from the nearest of 1 024 table points: error at most
/// `sin(π/1024)` + 2^-15 = 3.1e-3 (for terms of a few arcseconds, where that is 0.02″). Not inlined: it
/// is called 36 times, and a call costs a few cycles but saves about 1.5 KB of MSP430 flash.
#[inline(never)]
fn cos16(u: u16) -> i16 {
    let i = u.wrapping_add(32) >> 6;
    let k = usize::from(i & 0xFF);
    let q = (i >> 8) & 3;
    let v = if q & 1 == 0 {
        QUARTER_COS.get(k).copied().unwrap_or(1 << 30)
    } else {
        QUARTER_COS.get(256 - k).copied().unwrap_or(0)
    };
    // The high half of Q30, rounded, is Q14 (|v| ≤ 2^30, so it fits i16).
    let v = ((v + 0x8000) >> 16) as i16;
    if q == 1 || q == 2 {
        -v
    } else {
        v
    }
}

/// `a·c` for an amplitude `a` and a Q14 cosine `c`, as i32 (16×16 → 32 bits, exact). Out of
/// line on the MSP430 (called 29 times from 11 places: 0.35 KB less flash for ≈ 300 cycles).
#[cfg_attr(target_arch = "msp430", inline(never))]
fn scaled(a: i16, c: i16) -> i32 {
    i32::from(a) * i32::from(c)
}

/// Nearest integer of `x` for |x| < 2^22 (ties to even), by adding 1.5·2^23: the sum's low
/// mantissa bits are the integer. Exact, and a third of the cost of a saturating `as i32` on the
/// MSP430 (which a value out of range cannot reach here: it would only give a wrong angle).
fn round_small(x: f32) -> i32 {
    const MAGIC: f32 = 12_582_912.0;
    ((x + MAGIC).to_bits() as i32).wrapping_sub(0x4B40_0000)
}

/// `(sin, cos)` of `x` turns (|x| ≤ 2): the nearest table point `a` plus the second-order
/// correction `sin(a + δ) = sin a (1 − δ²/2) + cos a δ` (error δ³/6 ≤ 5e-9 for |δ| ≤ π/1024,
/// plus f32 rounding of a few 1e-8). `x·1024` is exact, so no floating range reduction is lost.
fn sincos_turns(x: f32) -> (f32, f32) {
    const Q30: f32 = 1.0 / 1_073_741_824.0;
    let u = x * 1024.0;
    let k = round_small(u);
    let delta = (u - k as f32) * (core::f32::consts::TAU / 1024.0);
    let (s, c) = table_sin_cos(k as u16);
    let (s, c) = (s as f32, c as f32);
    // The Q30 scale folded into the factors (exact: a power of two).
    let w = (1.0 - 0.5 * delta * delta) * Q30;
    let delta = delta * Q30;
    (s * w + c * delta, c * w - s * delta)
}

/// An angle in turns to 2^-16 turn (nearest, wrapping), |x| < 64 turns.
fn turn16(x: f32) -> u16 {
    round_small(x * 65_536.0) as u16
}

/// A fundamental argument at `n` whole days plus `f_q15` 2^-15 days (|f_q15| ≤ 2^14), 2^-16 turn:
/// exact fixed point for the whole days (wrapping 32-bit turns: the rate's 2^-33 turn/day
/// rounding is 5e-6 turn after 150 years), 1 unit/day rate rounding times ½ day for the fraction.
#[cfg_attr(target_arch = "msp430", inline(never))]
fn at(arg: &Fundamental, n: i32, f_q15: i16) -> u16 {
    let whole = arg
        .phase_q32
        .wrapping_add(arg.rate_q32.wrapping_mul(n as u32));
    let frac = scaled(arg.rate_q16, f_q15) >> 15;
    ((whole >> 16) as u16).wrapping_add(frac as u16)
}

/// `k·x` modulo 2^16 for the small multipliers of the periodic terms (|k| ≤ 5), by shift and add:
/// a multiply is a library call of about 80 cycles on the MSP430 without multiplier.
fn times(x: u16, k: i8) -> u16 {
    let (mut m, mut x, mut acc) = (k.unsigned_abs(), x, 0u16);
    while m != 0 {
        if m & 1 != 0 {
            acc = acc.wrapping_add(x);
        }
        x = x.wrapping_shl(1);
        m >>= 1;
    }
    if 0 > k {
        acc.wrapping_neg()
    } else {
        acc
    }
}

/// `c[0] + c[1] x + c[2] x² + …` (Horner). Out of line on the MSP430 (10 calls).
#[cfg_attr(target_arch = "msp430", inline(never))]
fn poly(c: &[f32], x: f32) -> f32 {
    let mut it = c.iter().rev();
    let mut acc = it.next().copied().unwrap_or(0.0);
    for &k in it {
        acc = acc * x + k;
    }
    acc
}

/// Nutation (Δψ, Δε) in rad from the arguments Ω (`node`), L☉ (`sun_lon`), D and M' in 2^-16
/// turn: the terms of arguments Ω, 2L☉, 2L☾ = 2(D + L☉), 2Ω, l′ = M' + 90°, with
/// `sin x = cos(x − 90°)`.
fn nutation(node: u16, sun_lon: u16, d: u16, e: u16) -> (f32, f32) {
    const QUARTER: u16 = 16_384;
    let two_sun = sun_lon.wrapping_mul(2);
    let two_moon = d.wrapping_add(sun_lon).wrapping_mul(2);
    let two_node = node.wrapping_mul(2);
    // Σ amplitude (0.001″) × Q14 cosine: |sum| ≤ 19 095 · 2^14 < 2^31. Loops (for flash): the
    // integer sums do not depend on the order. l′ enters as M' + 90°.
    let args = [node, two_sun, two_moon, two_node, e.wrapping_add(QUARTER)];
    let mut dpsi: i32 = 0;
    for (&x, &p) in args.iter().zip(&DPSI_MAS) {
        dpsi = dpsi.wrapping_add(scaled(p, cos16(x.wrapping_sub(QUARTER))));
    }
    let mut deps: i32 = 0;
    for (&x, &q) in args.iter().zip(&DEPS_MAS) {
        deps = deps.wrapping_add(scaled(q, cos16(x)));
    }
    let (dpsi, deps) = (dpsi as f32 * NUT_SUM_UNIT, deps as f32 * NUT_SUM_UNIT);
    (dpsi, deps)
}

/// The apparent Sun at a UTC instant: unit vector in TEME of date and distance in AU.
///
/// TT = UTC + ΔAT + 32.184 s from the leap-second table
/// ([`Epoch::<Utc>::to_tt_extrapolated`]: after the table's end no new leap second is assumed,
/// which moves the Sun by at most 0.04″ per missing second).
///
/// # Errors
/// [`SunError::Time`] before 1972 (no leap-second UTC) or for a 23:59:60 that did not exist;
/// [`SunError::Year`] after 2100.
#[cfg_attr(target_arch = "msp430", inline(never))]
pub fn sun(epoch: &Epoch<Utc>) -> Result<Sun, SunError> {
    sun_tt(&epoch.to_tt_extrapolated()?)
}

/// The apparent Sun at a TT instant: unit vector in TEME of date and distance in AU.
///
/// Years (TT) outside 1950..=2100 give [`SunError::Year`].
pub fn sun_tt(epoch: &Epoch<Tt>) -> Result<Sun, SunError> {
    let n = epoch.day();
    if !(n >= FIRST_DAY && LAST_DAY >= n) {
        return Err(SunError::Year(year_of_day(n)));
    }
    // Days since J2000.0 = 2000-01-01 12:00 TT: n whole days + f, f in −0.5..0.5.
    let f = (epoch.second_of_day() as f32 + epoch.nano() as f32 * 1e-9) * (1.0 / 86_400.0) - 0.5;
    let f_q15 = round_small(f * 32_768.0) as i16;
    let days = n as f32 + f;
    let tau = days * (1.0 / 365_250.0);
    let t = tau * 10.0;

    // Mean longitude and M' (turns); cos kM', sin kM' for k = 1, 2.
    let lon_mean = MEAN_LONGITUDE.turns(n, f);
    let m = lon_mean + (M_OFFSET + M_RATE * tau);
    let (s1, c1) = sincos_turns(m);
    let s2 = (s1 + s1) * c1;
    let c2 = 1.0 - (s1 + s1) * s1;

    // Equation of the centre and slow terms (rad, AU).
    // c1·L1c + s1·L1s + c2·L2c + s2·L2s + slow, summed left to right (as a loop, for flash).
    let mut dl = c1 * poly(&L1_COS, tau);
    let mut r_au = c1 * poly(&R1_COS, tau);
    let series: [(f32, &[f32], &[f32]); 3] = [
        (s1, &L1_SIN, &R1_SIN),
        (c2, &L2_COS, &R2_COS),
        (s2, &L2_SIN, &R2_SIN),
    ];
    for (x, l, r) in series {
        dl += x * poly(l, tau);
        r_au += x * poly(r, tau);
    }
    dl += poly(&SLOW_L, tau);
    r_au += poly(&SLOW_R, tau);

    // Fundamental arguments, 2^-16 turn.
    let e = turn16(m);
    let v = at(&VENUS, n, f_q15);
    let ma = at(&MARS, n, f_q15);
    let j = at(&JUPITER, n, f_q15);
    let s = at(&SATURN, n, f_q15);
    let d = at(&ELONGATION, n, f_q15);
    let node = at(&NODE, n, f_q15);
    let sun_lon = turn16(lon_mean);

    // Planetary and lunar terms: argument = Σ k·(M', V, Ma, J, S, D) + phase.
    // Σ amplitude × Q14 cosine in i32: Σ|A_L| = 106 730 and Σ|A_R| = 89 020 units, times 2^14 < 2^31.
    let fundamentals = [e, v, ma, j, s, d];
    let mut sum_l: i32 = 0;
    let mut sum_r: i32 = 0;
    for t in &TERMS {
        let mut arg: u16 = 0;
        for &(i, k) in &t.args {
            let x = fundamentals.get(usize::from(i)).copied().unwrap_or(0);
            arg = arg.wrapping_add(times(x, k));
        }
        sum_l = sum_l.wrapping_add(scaled(t.l_amp, cos16(arg.wrapping_add(t.l_phase))));
        if t.r_amp != 0 {
            sum_r = sum_r.wrapping_add(scaled(t.r_amp, cos16(arg.wrapping_add(t.r_phase))));
        }
    }
    dl += sum_l as f32 * (L_UNIT / 16_384.0) as f32;
    r_au += sum_r as f32 * (R_UNIT / 16_384.0) as f32;

    let (dpsi, deps) = nutation(node, sun_lon, d, e);

    // λ_app = λ − 0.09033″ (FK5) + Δψ − 20.4898″/R, in turns.
    dl += dpsi - 0.090_33 * ARCSEC - 20.4898 * ARCSEC / r_au;
    let lon_app = lon_mean + dl * (1.0 / core::f32::consts::TAU);

    // True equator and equinox of date (β = 0); ε = ε₀ + dε to first order (dε ≤ 2.8e-4 rad,
    // second order 2e-8).
    let (sin_lon, cos_lon) = sincos_turns(lon_app);
    let d_eps = EPS_RATE * t + deps;
    let sin_eps = SIN_EPS0 + COS_EPS0 * d_eps;
    let cos_eps = COS_EPS0 - SIN_EPS0 * d_eps;
    let x_tod = cos_lon;
    let y_tod = sin_lon * cos_eps;
    let z_tod = sin_lon * sin_eps;
    // TEME: rotate by the equation of the equinoxes about z (α_TEME = α_TOD − Δψ cos ε̄);
    // first order is exact to 3e-9 for |Δψ cos ε̄| < 9e-5 rad; cos ε̄ ≈ cos ε₀ to 0.002″.
    let eqeq = dpsi * COS_EPS0;
    let direction = Vec3::new(x_tod + eqeq * y_tod, y_tod - eqeq * x_tod, z_tod);
    Ok(Sun {
        direction,
        distance_au: r_au,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_sine_cosine_is_exact_to_f32() {
        for i in 0..4096u32 {
            let x = f64::from(i) / 4096.0 * 3.0 - 1.5 + 1e-4;
            let (s, c) = sincos_turns(x as f32);
            let a = f64::from(x as f32) * core::f64::consts::TAU;
            assert!((f64::from(s) - a.sin()).abs() < 1.5e-7, "{x}");
            assert!((f64::from(c) - a.cos()).abs() < 1.5e-7, "{x}");
        }
        for u in 0..=u16::MAX {
            let a = f64::from(u) / 65_536.0 * core::f64::consts::TAU;
            assert!((f64::from(cos16(u)) / 16_384.0 - a.cos()).abs() < 3.1e-3);
        }
    }

    /// The Sun's five-term nutation against the crate's 40-term IAU-1980 series (f64).
    #[test]
    fn truncated_nutation_against_frames_nutation() {
        let arcsec = core::f64::consts::PI / 648_000.0;
        let (mut max_psi, mut max_eps) = (0.0f64, 0.0f64);
        // f = 0.25 day: 8 192 in 2^-15 day.
        let mut n = FIRST_DAY;
        while n <= LAST_DAY {
            let f = 0.25f32;
            let days = n as f32 + f;
            let tau = days * (1.0 / 365_250.0);
            let lon_mean = MEAN_LONGITUDE.turns(n, f);
            let m = lon_mean + (M_OFFSET + M_RATE * tau);
            let (dpsi, deps) = nutation(
                at(&NODE, n, 8_192),
                turn16(lon_mean),
                at(&ELONGATION, n, 8_192),
                turn16(m),
            );
            let t = (f64::from(n) + f64::from(f)) / 36_525.0;
            let full = crate::frames::nutation::nutation(t);
            max_psi = max_psi.max((f64::from(dpsi) - full.dpsi_rad).abs() / arcsec);
            max_eps = max_eps.max((f64::from(deps) - full.deps_rad).abs() / arcsec);
            n += 3;
        }
        println!("Sun nutation (5 terms) vs frames::nutation (40 terms), 1950-2100: dpsi max {max_psi:.3}\", deps max {max_eps:.3}\"");
        assert!(max_psi < 0.3 && max_eps < 0.12);
    }
}
