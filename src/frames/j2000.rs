//! TEME (true equator, mean equinox of date) → J2000 (mean equator and equinox of J2000.0), the
//! output conversion: IAU-1976 precession, IAU-1980 [`nutation`](super::nutation) and the
//! equation of the equinoxes (Vallado 2013 §3.7 and algorithm `teme2eci`; Vallado et al. 2006,
//! "Revisiting Spacetrack Report #3", AIAA 2006-6753):
//! ```text
//! r_J2000 = P(ζ, θ, z) · N(ε̄, Δψ, ε) · R3(−Δψ cos ε̄) · r_TEME
//! P = R3(ζ) R2(−θ) R3(z)            (mean of date → J2000, Vallado 2013 eq. 3-88)
//! N = R1(−ε̄) R3(Δψ) R1(ε)           (true of date → mean of date, eq. 3-86)
//! ```
//! with the passive elementary rotations of [`crate::attitude`] (`R3(α) = [[c, s, 0], [−s, c,
//! 0], [0, 0, 1]]`) and the precession angles of Lieske et al. (1977) (eq. 3-87):
//! ```text
//! ζ = 2306.2181″ T + 0.301 88″ T² + 0.017 998″ T³
//! θ = 2004.3109″ T − 0.426 65″ T² − 0.041 833″ T³
//! z = 2306.2181″ T + 1.094 68″ T² + 0.018 203″ T³
//! ```
//! `T` in Julian centuries of TT. Velocities are rotated by the same matrix (its rate, < 2e-10
//! rad/s, changes them by < 2e-6 m/s).
//!
//! # Accuracy (measured, `cargo test --test frames j2000 -- --nocapture`)
//! On the DTUSAT week of `tests/data/sgp4/dtusat_wgs72_{teme,j2000}.e` (10 081 rows,
//! 2009-06-15 … 22, |r| ≈ 7200 km), every TEME row rotated to J2000 matches the J2000 row within
//! 0.94 m (RMS 0.88 m, 0.027″); velocities within 1e-3 m/s. With f32 vectors (km) and matrix:
//! 1.9 m. About 0.5 m of the residual goes away if the 23 mas frame bias J2000 → GCRS is
//! applied, so the reference is likely GCRS-based (IAU-2000/2006); the IAU-76/80 model itself
//! is good to a few tens of mas over these years. The [`nutation`](super::nutation) truncation
//! contributes ≤ 0.0025″ (9 cm).

use super::nutation::{nutation, Nutation};
use super::Real;
use crate::time::{Epoch, Tt};
use nalgebra::{Matrix3, Vector3};

/// One arcsecond in radians.
const ARCSEC_RAD: f64 = core::f64::consts::PI / 648_000.0;

/// Passive rotation about x (`R1`).
fn rot1<T: Real>(angle_rad: T) -> Matrix3<T> {
    let (s, c) = angle_rad.sincos();
    let (zero, one) = (T::of(0.0), T::of(1.0));
    Matrix3::new(one, zero, zero, zero, c, s, zero, -s, c)
}

/// Passive rotation about y (`R2`).
fn rot2<T: Real>(angle_rad: T) -> Matrix3<T> {
    let (s, c) = angle_rad.sincos();
    let (zero, one) = (T::of(0.0), T::of(1.0));
    Matrix3::new(c, zero, -s, zero, one, zero, s, zero, c)
}

/// Passive rotation about z (`R3`).
fn rot3<T: Real>(angle_rad: T) -> Matrix3<T> {
    let (s, c) = angle_rad.sincos();
    let (zero, one) = (T::of(0.0), T::of(1.0));
    Matrix3::new(c, s, zero, -s, c, zero, zero, zero, one)
}

/// IAU-1976 precession, mean of date → J2000: `r_J2000 = P · r_MOD`, at `t` Julian centuries
/// of TT since J2000.0.
pub fn mod_to_j2000_matrix<T: Real>(t: T) -> Matrix3<T> {
    let arcsec = T::of(ARCSEC_RAD);
    // ζ, θ, z (Lieske et al. 1977)
    let zeta = ((T::of(0.017_998) * t + T::of(0.301_88)) * t + T::of(2_306.218_1)) * t * arcsec;
    let theta = ((T::of(-0.041_833) * t - T::of(0.426_65)) * t + T::of(2_004.310_9)) * t * arcsec;
    let z = ((T::of(0.018_203) * t + T::of(1.094_68)) * t + T::of(2_306.218_1)) * t * arcsec;
    rot3(zeta) * rot2(-theta) * rot3(z)
}

/// Nutation, true of date → mean of date: `r_MOD = N · r_TOD`, `N = R1(−ε̄) R3(Δψ) R1(ε)`.
pub fn tod_to_mod_matrix<T: Real>(n: &Nutation<T>) -> Matrix3<T> {
    rot1(-n.mean_obliquity_rad) * rot3(n.dpsi_rad) * rot1(n.true_obliquity_rad())
}

/// TEME → true of date: `r_TOD = R3(−Δψ cos ε̄) · r_TEME` (the equinox moves from mean to true).
pub fn teme_to_tod_matrix<T: Real>(n: &Nutation<T>) -> Matrix3<T> {
    rot3(-n.equation_of_equinoxes_rad())
}

/// TEME → J2000 at `t` Julian centuries of TT since J2000.0: `r_J2000 = M · r_TEME` (module
/// docs). Its transpose maps J2000 → TEME.
pub fn teme_to_j2000_matrix_at<T: Real>(t: T) -> Matrix3<T> {
    let n = nutation(t);
    mod_to_j2000_matrix(t) * tod_to_mod_matrix(&n) * teme_to_tod_matrix(&n)
}

/// TEME → J2000 at a TT epoch: `r_J2000 = M · r_TEME` (see [`teme_to_j2000_matrix_at`]).
pub fn teme_to_j2000_matrix<T: Real>(tt: &Epoch<Tt>) -> Matrix3<T> {
    teme_to_j2000_matrix_at(T::of(tt.julian_centuries_since_j2000_f64()))
}

/// A TEME state (km, km/s) in J2000 at the TT epoch `tt`. Returns `(r_j2000_km, v_j2000_kmps)`.
pub fn teme_to_j2000<T: Real>(
    r_teme_km: &Vector3<T>,
    v_teme_kmps: &Vector3<T>,
    tt: &Epoch<Tt>,
) -> (Vector3<T>, Vector3<T>) {
    let m = teme_to_j2000_matrix(tt);
    (m * r_teme_km, m * v_teme_kmps)
}

/// A J2000 state (km, km/s) in TEME at the TT epoch `tt`, the inverse of [`teme_to_j2000`].
/// Returns `(r_teme_km, v_teme_kmps)`.
pub fn j2000_to_teme<T: Real>(
    r_j2000_km: &Vector3<T>,
    v_j2000_kmps: &Vector3<T>,
    tt: &Epoch<Tt>,
) -> (Vector3<T>, Vector3<T>) {
    let mt = teme_to_j2000_matrix::<T>(tt).transpose();
    (mt * r_j2000_km, mt * v_j2000_kmps)
}
