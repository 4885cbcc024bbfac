//! The precise Sun: apparent geocentric direction of date in TEME, and distance.
//!
//! # Method
//! 1. Geometric heliocentric ecliptic longitude `L` and radius `R` of the Earth from VSOP87D
//!    (P. Bretagnon, G. Francou, A&A 202, 309, 1988) as abridged by J. Meeus, *Astronomical
//!    Algorithms*, 2nd ed., ch. 25 "higher accuracy" and appendix III, truncated further here:
//!    `L0` keeps its 16 periodic terms of amplitude ≥ 500e-8 rad (≥ 1″), `L1` its linear term
//!    (folded into the mean longitude) and its largest periodic term, `L2…L5` and the latitude
//!    `B` (≤ 0.6″) are dropped. Each `R` term is in quadrature with the `L0` term of the same
//!    frequency (phases differ by ±π/2 to within 0.03 rad, checked by a unit test), so one
//!    `sincos` per frequency gives both.
//! 2. Geocentric Sun: `λ = L + 180°`, `β = 0`; the FK5 correction −0.09033″ (Meeus eq. 25.9).
//! 3. Nutation in longitude `Δψ` and obliquity `Δε` (IAU 1980) and the mean obliquity `ε̄`
//!    (IAU 1976), from [`crate::frames::nutation`].
//! 4. Aberration (with the light time of the Sun's apparent motion): `−20.4898″ / R`
//!    (Meeus eq. 25.10); apparent longitude `λ_app = λ + Δψ − 20.4898″/R`.
//! 5. True equator of date with `ε = ε̄ + Δε`; then TEME (true equator, **mean** equinox): the
//!    right ascension decreases by the equation of the equinoxes `Δψ·cos ε̄`.
//!
//! # Symbols
//! | name | symbol | meaning |
//! |---|---|---|
//! | `n`, `f` | | whole days and fraction since J2000.0 (2000-01-01 12:00 TT) |
//! | `tau` | τ | Julian millennia of TT since J2000.0 |
//! | `t` | T | Julian centuries of TT since J2000.0 |
//! | `lon_geo` | λ | geometric geocentric ecliptic longitude, mean equinox of date |
//! | `r_au` | R | Earth–Sun distance (AU) |
//! | `dpsi`, `deps` | Δψ, Δε | nutation in longitude and obliquity |
//! | `eps` | ε | true obliquity of the ecliptic |
//! | `eqeq` | | equation of the equinoxes `Δψ cos ε̄` |
//!
//! # Precision
//! Every argument `B + C·τ` is reduced modulo 2π in exact fixed point from the whole day count
//! (`LinearAngle`) before any f32 product, so f32 rounding adds well under 1″.
//!
//! # Range and measured accuracy
//! Years 1950–2100 in TT ([`sun_tt`]); from UTC ([`sun`]) 1972–2100, the leap-second era. Other
//! years give [`SunError`]. Against the apparent Sun of JPL DE421 in TEME of date
//! (`../shared/ref/sun/sun_de421.csv`, 400 instants 1990–2050, UTC input): **max 3.72″, RMS
//! 1.43″**; distance max 1.3e-5 AU (`cargo test --test sun -- --nocapture`, which holds 15″ and
//! 2e-5 AU on every row). Over the whole range 1950–2100 (every 5 days) it is within 4.70″ (RMS
//! 1.46″) of the full abridged series of Meeus in f64, which is itself within 0.46″ of DE421 on
//! the reference rows (test `precise_truncation_over_1950_2100`).

use super::{year_of_day, LinearAngle, Sun, SunError};
use crate::fmath;
use crate::frames::nutation::nutation;
use crate::linalg::Vec3;
use crate::time::{Epoch, Tt, Utc};

/// One arcsecond in radians.
const ARCSEC: f32 = (core::f64::consts::PI / 648_000.0) as f32;

/// A VSOP87 longitude term `a·cos(B + C·τ)` with the radius term of the same frequency,
/// `a_r·cos(B_r + C·τ) = ±a_r·sin(B + C·τ)` (the sign folded into `r_sin`).
struct Term {
    /// Amplitude of the longitude term, radians.
    l_cos: f32,
    /// Radius coefficient of `sin(B + C·τ)`, AU.
    r_sin: f32,
    /// The argument `B + C·τ`.
    arg: LinearAngle,
}

/// Builds a [`Term`] from Meeus's table entries: longitude `(A, B, C)` in 1e-8 rad, rad,
/// rad/millennium, and the radius term `(A_r, B_r)` of the same frequency (`A_r = 0` if none).
const fn term(a: f64, b: f64, c: f64, a_r: f64, b_r: f64) -> Term {
    // cos(x + B_r − B) with B_r − B = −π/2 + δ is sin(x); with +π/2 + δ it is −sin(x).
    let mut d = b_r - b;
    let pi = core::f64::consts::PI;
    while d > pi {
        d -= 2.0 * pi;
    }
    while d <= -pi {
        d += 2.0 * pi;
    }
    let sign = if d < 0.0 { 1.0 } else { -1.0 };
    Term {
        l_cos: (a * 1e-8) as f32,
        r_sin: (sign * a_r * 1e-8) as f32,
        arg: LinearAngle::from_radians_per_millennium(b, c),
    }
}

/// VSOP87D Earth, `L0` terms ≥ 500e-8 rad with their `R0` partners (Meeus appendix III).
#[allow(clippy::unreadable_literal)] // as printed by Meeus
const L0_TERMS: [Term; 16] = [
    term(3341656.0, 4.6692568, 6283.07585, 1670700.0, 3.0984635),
    term(34894.0, 4.6261, 12566.1517, 13956.0, 3.05525),
    term(3497.0, 2.7441, 5753.3849, 1628.0, 1.1739),
    term(3418.0, 2.8289, 3.5231, 0.0, 0.0),
    term(3136.0, 3.6277, 77713.7715, 3084.0, 5.1985),
    term(2676.0, 4.4181, 7860.4194, 1576.0, 2.8469),
    term(2343.0, 6.1352, 3930.2097, 542.0, 4.564),
    term(1324.0, 0.7425, 11506.7698, 925.0, 5.453),
    term(1273.0, 2.0371, 529.691, 0.0, 0.0),
    term(1199.0, 1.1096, 1577.3435, 212.0, 5.847),
    term(990.0, 5.233, 5884.927, 472.0, 3.661),
    term(902.0, 2.045, 26.298, 0.0, 0.0),
    term(857.0, 3.508, 398.149, 0.0, 0.0),
    term(780.0, 1.179, 5223.694, 329.0, 5.9),
    term(753.0, 2.533, 5507.553, 346.0, 0.964),
    term(505.0, 4.583, 18849.228, 175.0, 3.012),
];

/// The largest periodic `L1` term (×τ) with its `R1` partner.
#[allow(clippy::unreadable_literal)]
const L1_TERM: Term = term(206059.0, 2.678235, 6283.07585, 103019.0, 1.10749);

/// Mean longitude of the Sun: the constant of `L0` and the linear term of `L1`, plus 180°.
const MEAN_LONGITUDE: LinearAngle = LinearAngle::from_radians_per_millennium(
    1.753_470_46 + core::f64::consts::PI,
    6_283.319_667_47,
);

/// Constant of `R0` (AU).
const R0_CONST: f32 = 1.000_139_89_f64 as f32;

/// The apparent Sun at a UTC instant: unit vector in TEME of date and distance in AU.
///
/// TT = UTC + ΔAT + 32.184 s from the leap-second table
/// ([`Epoch::<Utc>::to_tt_extrapolated`]: after the table's end no new leap second is assumed,
/// which moves the Sun by at most 0.04″ per missing second).
///
/// # Errors
/// [`SunError::Time`] before 1972 (no leap-second UTC) or for a 23:59:60 that did not exist;
/// [`SunError::Year`] after 2100.
pub fn sun(epoch: &Epoch<Utc>) -> Result<Sun, SunError> {
    sun_tt(&epoch.to_tt_extrapolated()?)
}

/// The apparent Sun at a TT instant: unit vector in TEME of date and distance in AU.
///
/// Years (TT) outside 1950..=2100 give [`SunError::Year`].
pub fn sun_tt(epoch: &Epoch<Tt>) -> Result<Sun, SunError> {
    let year = year_of_day(epoch.day());
    if !(1950..=2100).contains(&year) {
        return Err(SunError::Year(year));
    }
    // Days since J2000.0 = 2000-01-01 12:00 TT: n whole days + f, f in −0.5..=0.5.
    let n = epoch.day();
    let (_, f) = epoch.days_since_j2000_split();
    let days = n as f32 + f;
    let tau = days / 365_250.0;
    let t = epoch.julian_centuries_since_j2000_f32();

    // L = L0 + L1·τ (VSOP87D), λ = L + 180°; R likewise.
    let mut lon_geo = MEAN_LONGITUDE.radians(n, f);
    let mut r_au = R0_CONST;
    for term in &L0_TERMS {
        let (s, c) = fmath::sincos(term.arg.radians(n, f));
        lon_geo += term.l_cos * c;
        r_au += term.r_sin * s;
    }
    let (s, c) = fmath::sincos(L1_TERM.arg.radians(n, f));
    lon_geo += tau * L1_TERM.l_cos * c;
    r_au += tau * L1_TERM.r_sin * s;

    // Nutation (IAU 1980) and true obliquity ε = ε̄ + Δε (IAU 1976), from crate::frames.
    let nut = nutation(t);
    let dpsi = nut.dpsi_rad;
    let eps = nut.true_obliquity_rad();

    // λ_app = λ − 0.09033″ (FK5) + Δψ − 20.4898″/R
    let lon_app = lon_geo - 0.090_33 * ARCSEC + dpsi - 20.4898 * ARCSEC / r_au;

    // True equator and equinox of date (β = 0).
    let (sin_lon, cos_lon) = fmath::sincos(lon_app);
    let (sin_eps, cos_eps) = fmath::sincos(eps);
    let x_tod = cos_lon;
    let y_tod = sin_lon * cos_eps;
    let z_tod = sin_lon * sin_eps;
    // TEME: rotate by the equation of the equinoxes about z (α_TEME = α_TOD − Δψ cos ε̄);
    // first order is exact to 3e-9 for |Δψ cos ε̄| < 9e-5 rad.
    let eqeq = nut.equation_of_equinoxes_rad();
    let direction = Vec3::new(x_tod + eqeq * y_tod, y_tod - eqeq * x_tod, z_tod);
    Ok(Sun {
        direction,
        distance_au: r_au,
    })
}

#[cfg(test)]
mod tests {
    /// The radius terms are folded into the longitude terms' sines: check that each pair of
    /// phases differs by ±π/2 within 0.03 rad (so the folding error is < 0.03·A_r ≤ 1e-7 AU).
    #[test]
    fn radius_terms_are_in_quadrature() {
        let pairs: [(f64, f64, f64); 13] = [
            (4.669_256_8, 3.098_463_5, 1_670_700.0),
            (4.6261, 3.055_25, 13_956.0),
            (2.7441, 1.1739, 1_628.0),
            (3.6277, 5.1985, 3_084.0),
            (4.4181, 2.8469, 1_576.0),
            (6.1352, 4.564, 542.0),
            (0.7425, 5.453, 925.0),
            (1.1096, 5.847, 212.0),
            (5.233, 3.661, 472.0),
            (1.179, 5.9, 329.0),
            (2.533, 0.964, 346.0),
            (4.583, 3.012, 175.0),
            (2.678_235, 1.107_49, 103_019.0),
        ];
        for (b, b_r, a_r) in pairs {
            let d = (b_r - b).rem_euclid(core::f64::consts::TAU);
            let off = (d - core::f64::consts::FRAC_PI_2)
                .abs()
                .min((d - 3.0 * core::f64::consts::FRAC_PI_2).abs());
            assert!(off < 0.03, "phase pair {b} {b_r}: off by {off}");
            assert!(off * a_r * 1e-8 < 1e-7);
        }
    }
}
