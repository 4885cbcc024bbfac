//! Schlyter's Sun model: P. Schlyter's algorithm, the thesis's Sun model (seed 000 §7.1).
//!
//! Source: P. Schlyter, "How to compute planetary positions" (stjarnhimlen.se), the thesis's
//! ref. \[8\]; the thesis's §7.1 and eqs. 7.1–7.9 (note 000 §3.4). Kept exactly as the thesis has it,
//! so that its numbers are reproduced; the project's accurate model is [`super::precise`].
//!
//! The Earth's orbit is a fixed Kepler ellipse with slowly drifting perigee, eccentricity and
//! obliquity; the result is the geometric Sun in the equator and **mean** equinox **of date** as
//! the algorithm defines them (no nutation, no aberration, no light time), taken by the thesis as
//! its inertial IJK frame.
//!
//! # Symbols (seed 000 §7.1)
//! | name | symbol | meaning |
//! |---|---|---|
//! | `d` | d | days since 1999-12-31 00:00 UT (`d = JD − 2451543.5`, note 000 §7.7), UT taken as UTC |
//! | `w` | w | argument of perihelion (of the Sun's apparent orbit) |
//! | `e` | e | eccentricity |
//! | `m` | M | mean anomaly |
//! | `ecc_anom` | E | eccentric anomaly, one-step approximation `E = M + e sin M (1 + e cos M)` |
//! | `xv`, `yv` | xv, yv | position in the orbit plane (AU) |
//! | `v`, `r` | v, r | true anomaly, distance (AU) |
//! | `lon` | lon_sun | ecliptic longitude `v + w` |
//! | `ecl` | ecl | obliquity of the ecliptic |
//!
//! # Precision
//! `d` is never formed as one f32: the mean anomaly is reduced modulo 360° exactly
//! (`LinearAngle`) from the whole day count, so the f32 model equals Schlyter's algorithm
//! in f64 to about 1e-5° at any instant, instead of the thesis's own f32 code, whose `d` had a
//! resolution of 2 minutes by 2050. The thesis's printed values (an f32 run) are reproduced within
//! 2e-4° (test `thesis_values` in `tests/sun.rs`).
//!
//! # Range and accuracy
//! Years 1900–2100 (Schlyter: "the 20th and 21st centuries"); other years give
//! [`SunError::Year`]. Against JPL DE421 (apparent Sun, TEME of date, 1990–2050) the direction is
//! off by up to 46.9″ (RMS 26.2″), `cargo test --test sun -- --nocapture`.

use super::{year_of_day, LinearAngle, Sun, SunError};
use crate::fmath;
use crate::linalg::Vec3;
use crate::time::{days_from_civil, Epoch, Utc};

/// First and last UTC day (since 2000-01-01) of the model's range, 1900-01-01 and 2100-12-31.
const FIRST_DAY: i32 = days_from_civil(1900, 1, 1);
const LAST_DAY: i32 = days_from_civil(2100, 12, 31);

/// M: 356.0470° + 0.9856002585°·d (Schlyter).
const MEAN_ANOMALY: LinearAngle = LinearAngle::from_degrees(356.0470, 0.985_600_258_5);

/// The Sun by Schlyter's algorithm (the thesis's) at a UTC instant (UT1 ≈ UTC, as in the thesis).
///
/// Returns the unit vector in the thesis's IJK (equator and mean equinox of date, no nutation)
/// and the distance in AU. Years outside 1900..=2100 give [`SunError::Year`].
pub fn sun(epoch: &Epoch<Utc>) -> Result<Sun, SunError> {
    // The range by day number (the calendar year only for the error: its divisions cost
    // thousands of MSP430 cycles).
    if !(epoch.day() >= FIRST_DAY && LAST_DAY >= epoch.day()) {
        return Err(SunError::Year(year_of_day(epoch.day())));
    }
    // d = whole + frac: day 0 of Epoch (2000-01-01) is d = 1 (note 000 §7.7).
    let whole = epoch.day().saturating_add(1);
    let frac = epoch.day_fraction_f32();
    let d = whole as f32 + frac;

    // w = 282.9404° + 4.70935e-5°·d
    let w = (282.9404 + 4.709_35e-5 * d).to_radians();
    // e = 0.016709 − 1.151e-9·d
    let e = 0.016_709 - 1.151e-9 * d;
    // M = 356.0470° + 0.9856002585°·d  (mod 360°)
    let m = MEAN_ANOMALY.radians(whole, frac);
    let (sin_m, cos_m) = fmath::sincos(m);
    // E = M + e·sin M·(1 + e·cos M)
    let ecc_anom = m + e * sin_m * (1.0 + e * cos_m);
    let (sin_e, cos_e) = fmath::sincos(ecc_anom);
    // xv = cos E − e,  yv = √(1 − e²)·sin E
    let xv = cos_e - e;
    let yv = fmath::sqrt(1.0 - e * e) * sin_e;
    // v = atan2(yv, xv),  r = √(xv² + yv²)
    let v = fmath::atan2(yv, xv);
    let r = fmath::sqrt(xv * xv + yv * yv);
    // lon = v + w
    let lon = v + w;
    // ecl = 23.4393° − 3.563e-7°·d
    let ecl = (23.4393 - 3.563e-7 * d).to_radians();
    let (sin_lon, cos_lon) = fmath::sincos(lon);
    let (sin_ecl, cos_ecl) = fmath::sincos(ecl);
    // (xe, ye, ze) / r = (cos lon, sin lon·cos ecl, sin lon·sin ecl)
    let direction = Vec3::new(cos_lon, sin_lon * cos_ecl, sin_lon * sin_ecl);
    Ok(Sun {
        direction,
        distance_au: r,
    })
}
