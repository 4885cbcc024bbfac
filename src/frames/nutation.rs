//! IAU-1980 nutation (Δψ, Δε), IAU-1976 mean obliquity ε̄ and the equation of the equinoxes,
//! truncated to the largest terms (the count chosen by measurement, below).
//!
//! # Source
//! - Series: Seidelmann (1982), "1980 IAU theory of nutation: the final report of the IAU
//!   Working Group on Nutation", Celest. Mech. 27, 79–106; as tabulated in Vallado 2013
//!   appendix D.6 (`nut80.dat`, same order) and the Explanatory Supplement (1992) table 3.222.1.
//!   The full 106-term table is `tests/data/iau1980_nutation.txt`.
//! - Fundamental arguments: IAU 1980 (Explanatory Supplement 1992 eq. 3.222-2; Vallado 2013
//!   eq. 3-82, the `'80'` option of his `fundarg`).
//! - Mean obliquity: Lieske et al. (1977), IAU-1976 (Vallado 2013 eq. 3-81; USNO Circular 163).
//! - Equation of the equinoxes for TEME: `Δψ cos ε̄` without the 1994 kinematic terms
//!   (0.00264″ sin Ω + 0.000063″ sin 2Ω), as in Vallado et al. (2006) "Revisiting Spacetrack
//!   Report #3", AIAA 2006-6753, and Vallado's `teme2eci`.
//!
//! # Symbols
//! | name | symbol | meaning |
//! |---|---|---|
//! | `t` | T | Julian centuries of TT since J2000.0 (2000-01-01 12:00 TT) |
//! | `l`, `l_sun`, `f`, `d`, `omega` | l, l′, F, D, Ω | Moon's and Sun's mean anomalies, Moon's argument of latitude, elongation, Moon's node |
//! | `dpsi_rad`, `deps_rad` | Δψ, Δε | nutation in longitude and in obliquity |
//! | `mean_obliquity_rad` | ε̄ | mean obliquity of the ecliptic |
//!
//! # Accuracy (measured against the full 106-term series over 1990–2050,
//! `cargo test --test frames nutation -- --nocapture`)
//! Truncation error of the rotation TEME → J2000 (`√((δψ sin ε̄)² + δε²)`), by term count:
//!
//! | terms | 5 | 10 | 13 | 20 | 30 | **40** | 60 | 106 |
//! |---|---|---|---|---|---|---|---|---|
//! | max error | 0.10″ | 0.031″ | 0.018″ | 0.0092″ | 0.0054″ | **0.0025″** | 0.0010″ | 0 |
//!
//! The crate evaluates [`TERM_COUNT`] = 40 terms (9 cm at 7000 km; 1″ needs only 5 terms, but
//! the series is cheap and the J2000 test then measures the model, not the truncation). In f32
//! against the full series: Δψ within 0.0061″, Δε within 0.0023″ (the Sun needs 0.5″).

use super::Real;

/// One term of the series: argument multipliers of (l, l′, F, D, Ω) and the coefficients
/// `Δψ += (a + b·T) sin(arg)`, `Δε += (c + d·T) cos(arg)` in units of 0.0001″.
#[derive(Copy, Clone, Debug, PartialEq)]
struct Term {
    k: [i8; 5],
    a: f32,
    b: f32,
    c: f32,
    d: f32,
}

const fn term(k: [i8; 5], a: f32, b: f32, c: f32, d: f32) -> Term {
    Term { k, a, b, c, d }
}

/// Number of terms of the series evaluated, the largest first (Vallado's order).
pub const TERM_COUNT: usize = 40;

/// The first [`TERM_COUNT`] terms of the IAU-1980 series (Seidelmann 1982 / Vallado 2013 D.6).
const TERMS: [Term; TERM_COUNT] = [
    term([0, 0, 0, 0, 1], -171996.0, -174.2, 92025.0, 8.9),
    term([0, 0, 2, -2, 2], -13187.0, -1.6, 5736.0, -3.1),
    term([0, 0, 2, 0, 2], -2274.0, -0.2, 977.0, -0.5),
    term([0, 0, 0, 0, 2], 2062.0, 0.2, -895.0, 0.5),
    term([0, -1, 0, 0, 0], -1426.0, 3.4, 54.0, -0.1),
    term([1, 0, 0, 0, 0], 712.0, 0.1, -7.0, 0.0),
    term([0, 1, 2, -2, 2], -517.0, 1.2, 224.0, -0.6),
    term([0, 0, 2, 0, 1], -386.0, -0.4, 200.0, 0.0),
    term([1, 0, 2, 0, 2], -301.0, 0.0, 129.0, -0.1),
    term([0, -1, 2, -2, 2], 217.0, -0.5, -95.0, 0.3),
    term([-1, 0, 0, 2, 0], 158.0, 0.0, -1.0, 0.0),
    term([0, 0, 2, -2, 1], 129.0, 0.1, -70.0, 0.0),
    term([-1, 0, 2, 0, 2], 123.0, 0.0, -53.0, 0.0),
    term([1, 0, 0, 0, 1], 63.0, 0.1, -33.0, 0.0),
    term([0, 0, 0, 2, 0], 63.0, 0.0, -2.0, 0.0),
    term([-1, 0, 2, 2, 2], -59.0, 0.0, 26.0, 0.0),
    term([-1, 0, 0, 0, 1], -58.0, -0.1, 32.0, 0.0),
    term([1, 0, 2, 0, 1], -51.0, 0.0, 27.0, 0.0),
    term([-2, 0, 0, 2, 0], -48.0, 0.0, 1.0, 0.0),
    term([-2, 0, 2, 0, 1], 46.0, 0.0, -24.0, 0.0),
    term([0, 0, 2, 2, 2], -38.0, 0.0, 16.0, 0.0),
    term([2, 0, 2, 0, 2], -31.0, 0.0, 13.0, 0.0),
    term([2, 0, 0, 0, 0], 29.0, 0.0, -1.0, 0.0),
    term([1, 0, 2, -2, 2], 29.0, 0.0, -12.0, 0.0),
    term([0, 0, 2, 0, 0], 26.0, 0.0, -1.0, 0.0),
    term([0, 0, 2, -2, 0], -22.0, 0.0, 0.0, 0.0),
    term([-1, 0, 2, 0, 1], 21.0, 0.0, -10.0, 0.0),
    term([0, 2, 0, 0, 0], 17.0, -0.1, 0.0, 0.0),
    term([0, 2, 2, -2, 2], -16.0, 0.1, 7.0, 0.0),
    term([-1, 0, 0, 2, 1], 16.0, 0.0, -8.0, 0.0),
    term([0, 1, 0, 0, 1], -15.0, 0.0, 9.0, 0.0),
    term([1, 0, 0, -2, 1], -13.0, 0.0, 7.0, 0.0),
    term([0, -1, 0, 0, 1], -12.0, 0.0, 6.0, 0.0),
    term([2, 0, -2, 0, 0], 11.0, 0.0, 0.0, 0.0),
    term([-1, 0, 2, 2, 1], -10.0, 0.0, 5.0, 0.0),
    term([1, 0, 2, 2, 2], -8.0, 0.0, 3.0, 0.0),
    term([0, -1, 2, 0, 2], -7.0, 0.0, 3.0, 0.0),
    term([0, 0, 2, 2, 1], -7.0, 0.0, 3.0, 0.0),
    term([1, 1, 0, -2, 0], -7.0, 0.0, 0.0, 0.0),
    term([0, 1, 2, 0, 2], 7.0, 0.0, -3.0, 0.0),
];

/// 0.0001″ in radians.
const UNIT_RAD: f64 = 1e-4 / 3600.0 * core::f64::consts::PI / 180.0;
/// One arcsecond in radians.
const ARCSEC_RAD: f64 = core::f64::consts::PI / 648_000.0;

/// Nutation angles and obliquity at an instant.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Nutation<T> {
    /// Nutation in longitude Δψ, rad.
    pub dpsi_rad: T,
    /// Nutation in obliquity Δε, rad.
    pub deps_rad: T,
    /// Mean obliquity of the ecliptic ε̄ (IAU-1976), rad.
    pub mean_obliquity_rad: T,
}

impl<T: Real> Nutation<T> {
    /// True obliquity ε = ε̄ + Δε, rad.
    pub fn true_obliquity_rad(&self) -> T {
        self.mean_obliquity_rad + self.deps_rad
    }

    /// The equation of the equinoxes `Δψ cos ε̄`, rad: right ascension from the mean equinox
    /// (TEME) to the true equinox (true of date), `α_TOD = α_TEME + eq_eq`. Without the 1994
    /// kinematic terms (≤ 0.0027″), as TEME is defined (module docs).
    pub fn equation_of_equinoxes_rad(&self) -> T {
        let (_, cos_eps) = self.mean_obliquity_rad.sincos();
        self.dpsi_rad * cos_eps
    }
}

/// Mean obliquity of the ecliptic (IAU-1976, Lieske et al. 1977; Vallado 2013 eq. 3-81):
/// `ε̄ = 84 381.448″ − 46.8150″ T − 0.000 59″ T² + 0.001 813″ T³`, rad.
pub fn mean_obliquity_rad<T: Real>(t: T) -> T {
    let arcsec =
        ((T::of(0.001_813) * t - T::of(0.000_59)) * t - T::of(46.815_0)) * t + T::of(84_381.448);
    arcsec * T::of(ARCSEC_RAD)
}

/// A fundamental argument in revolutions reduced to 0..1: `c0 + c1·T + c2·T² + c3·T³` with c0 in
/// degrees, c1 as whole revolutions plus arcseconds per century, c2 and c3 in arcseconds.
///
/// Always inlined: the coefficients are then constants of the caller and their f64 → `T`
/// conversions are done by the compiler (no f64 arithmetic on the MSP430).
#[inline(always)]
fn argument_rev<T: Real>(t: T, c0_deg: f64, rev: f64, c1_arcsec: f64, c2: f64, c3: f64) -> T {
    // Whole revolutions per century first, reduced on their own so the f32 sum stays small.
    let whole = T::of(rev) * t;
    let whole_frac = whole - whole.floor_();
    let rest_arcsec = ((T::of(c3) * t + T::of(c2)) * t + T::of(c1_arcsec)) * t;
    let x = whole_frac + T::of(c0_deg / 360.0) + rest_arcsec * T::of(1.0 / 1_296_000.0);
    x - x.floor_()
}

/// Nutation (IAU-1980, [`TERM_COUNT`] largest terms) and mean obliquity at `t` Julian centuries
/// of TT since J2000.0 (see [`crate::time::Epoch::julian_centuries_since_j2000_f64`]).
///
/// ```text
/// Δψ = Σ (Aᵢ + Bᵢ T) sin(aᵢ),  Δε = Σ (Cᵢ + Dᵢ T) cos(aᵢ),
/// aᵢ = k₁ l + k₂ l′ + k₃ F + k₄ D + k₅ Ω
/// ```
/// Use f64 for the J2000 output conversion and f32 in flight (Sun); see the module docs for the
/// measured truncation error.
pub fn nutation<T: Real>(t: T) -> Nutation<T> {
    // Fundamental arguments (IAU 1980), revolutions.
    let l = argument_rev(t, 134.962_981_39, 1325.0, 715_922.633, 31.310, 0.064);
    let l_sun = argument_rev(t, 357.527_723_33, 99.0, 1_292_581.224, -0.577, -0.012);
    let f = argument_rev(t, 93.271_910_28, 1342.0, 295_263.137, -13.257, 0.011);
    let d = argument_rev(t, 297.850_363_06, 1236.0, 1_105_601.328, -6.891, 0.019);
    let omega = argument_rev(t, 125.044_522_22, -5.0, -482_890.539, 7.455, 0.008);
    let args = [l, l_sun, f, d, omega];
    let two_pi = T::of(core::f64::consts::TAU);
    let mut dpsi = T::of(0.0);
    let mut deps = T::of(0.0);
    // Smallest terms first, so the f32 sums lose the least.
    for term in TERMS.iter().rev() {
        let mut arg_rev = T::of(0.0);
        for (k, x) in term.k.iter().zip(args.iter()) {
            arg_rev += T::of(f64::from(*k)) * *x;
        }
        let (s, c) = ((arg_rev - arg_rev.floor_()) * two_pi).sincos();
        dpsi += (T::of(f64::from(term.a)) + T::of(f64::from(term.b)) * t) * s;
        deps += (T::of(f64::from(term.c)) + T::of(f64::from(term.d)) * t) * c;
    }
    Nutation {
        dpsi_rad: dpsi * T::of(UNIT_RAD),
        deps_rad: deps * T::of(UNIT_RAD),
        mean_obliquity_rad: mean_obliquity_rad(t),
    }
}
