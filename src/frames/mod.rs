//! Reference frames: TEME, Earth-fixed (GMST), geodetic WGS-84, NED, geocentric spherical, RSW,
//! and (in [`j2000`]) the output conversion TEME → J2000 with the IAU-1980 [`nutation`].
//!
//! Every conversion is generic over [`Real`]: call it with f32 vectors ([`crate::linalg::Vec3`])
//! in flight code and with f64 vectors ([`crate::linalg::Vec3d`]) on the host; the f32 versions
//! use [`crate::fmath`].
//!
//! # Frames
//! | name | definition |
//! |---|---|
//! | TEME | SGP4's inertial frame: true equator of date, mean equinox of date (Vallado 2013 §3.7) |
//! | ECEF | Earth-fixed: TEME rotated by GMST (IAU-82) about z, i.e. Vallado's pseudo-Earth-fixed (PEF) frame; polar motion (≤ 0.5″, ≤ 15 m on the ground) is neglected |
//! | geodetic | WGS-84 latitude φ, east longitude λ, height h above the ellipsoid |
//! | NED | local North, East, Down at a geodetic (or geocentric) latitude and longitude |
//! | spherical | geocentric radius r, colatitude θ, east longitude (or right ascension) φ; components along r̂ (out), θ̂ (south), φ̂ (east), seed 000 eq. 7.26 |
//! | RSW | satellite frame: R radial, S along-track (completes the triad), W orbit normal (Vallado 2013 §3.3, seed 000 §2) |
//! | J2000 | mean equator and equinox of J2000.0 (FK5 / IAU-76/80), output only ([`j2000`]) |
//!
//! Matrices follow the crate's DCM convention ([`crate::attitude`]): a matrix named
//! `a_to_b_matrix` maps vectors as `v_b = M · v_a`, so its rows are `b`'s axes expressed in `a`.
//!
//! # Symbols
//! | name | symbol | meaning |
//! |---|---|---|
//! | `gmst_rad` | θ_GMST | Greenwich mean sidereal time ([`crate::time::gmst_rad`]) |
//! | `a`, `b`, `f`, `e2`, `ep2` | a, b, f, e², e′² | WGS-84 semi-axes, flattening, first and second eccentricity² |
//! | `n` | N | radius of curvature in the prime vertical, `a / √(1 − e² sin² φ)` |
//! | `p` | p | distance from the polar axis, `√(x² + y²)` |
//! | `u` | β | reduced (parametric) latitude |
//!
//! # Accuracy (measured, `cargo test --test frames -- --nocapture`)
//! - Rotations (TEME↔ECEF, NED, spherical, RSW): exact up to rounding, ≤ 3 ulp of |r|
//!   (f32: ≤ 1.5 m at 7000 km).
//! - [`ecef_to_geodetic`] (Bowring, 2 iterations), round trips over heights −10…40 000 km and
//!   all latitudes, poles included: f64 ≤ 2.3e-8 m; f32 (input rounded to f32, which alone
//!   moves it 0.5 m) ≤ 1.9 m, RMS 0.54 m in position for heights ≤ 2000 km, and ≤ 2.9e-7·|r|
//!   at any height (≤ 11 m in height at GEO, where the f32 resolution is 4 m).

pub mod j2000;
pub mod nutation;
mod real;
pub use j2000::{j2000_to_teme, teme_to_j2000, teme_to_j2000_matrix};
pub use real::Real;

use core::fmt;
use nalgebra::{Matrix3, Vector3};

/// WGS-84 semi-major axis, km.
pub const WGS84_A_KM: f64 = 6_378.137;
/// WGS-84 flattening `f = 1 / 298.257 223 563`.
pub const WGS84_F: f64 = 1.0 / 298.257_223_563;
/// Earth rotation rate ω⊕ in rad/s (Vallado 2013 eq. 3-40, nominal length of day; the value his
/// `teme2ecef` uses).
pub const EARTH_ROTATION_RADPS: f64 = 7.292_115_146_706_979e-5;
/// Positions closer than this to the Earth's centre have no unique geodetic coordinates (inside
/// the evolute of the meridian ellipse, 43 km) and are refused by [`ecef_to_geodetic`].
pub const GEODETIC_MIN_RADIUS_KM: f64 = 100.0;

/// Errors of the frame conversions.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum FrameError {
    /// An input was NaN or infinite.
    NonFinite,
    /// A position this close to the Earth's centre (km) where the conversion is not defined.
    NearCentre(f32),
    /// Degenerate geometry: a zero vector, or position parallel to velocity (RSW).
    Degenerate,
}

impl fmt::Display for FrameError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NonFinite => write!(f, "non-finite input"),
            Self::NearCentre(r) => write!(f, "position {r} km from the Earth's centre"),
            Self::Degenerate => {
                write!(
                    f,
                    "degenerate geometry (zero vector or position parallel to velocity)"
                )
            }
        }
    }
}

fn all_finite<T: Real>(v: &Vector3<T>) -> bool {
    v.x.finite() && v.y.finite() && v.z.finite()
}

/// The Euclidean norm, through [`Real::sqrt`] (so f32 uses [`crate::fmath`]).
fn norm<T: Real>(v: &Vector3<T>) -> T {
    Real::sqrt(v.dot(v))
}

// ---------------------------------------------------------------------------------------------
// TEME ↔ Earth-fixed
// ---------------------------------------------------------------------------------------------

/// The rotation TEME → ECEF, `R3(θ_GMST)`: `r_ecef = M · r_teme` (Vallado 2013 eq. 3-90 without
/// polar motion). Its transpose maps ECEF → TEME.
pub fn teme_to_ecef_matrix<T: Real>(gmst_rad: T) -> Matrix3<T> {
    let (s, c) = gmst_rad.sincos();
    let zero = T::of(0.0);
    Matrix3::new(c, s, zero, -s, c, zero, zero, zero, T::of(1.0))
}

/// A TEME position (any length unit) in ECEF: `r_ecef = R3(θ_GMST) · r_teme`.
pub fn teme_to_ecef_position<T: Real>(r_teme: &Vector3<T>, gmst_rad: T) -> Vector3<T> {
    teme_to_ecef_matrix(gmst_rad) * r_teme
}

/// An ECEF position (any length unit) in TEME: `r_teme = R3(−θ_GMST) · r_ecef`.
pub fn ecef_to_teme_position<T: Real>(r_ecef: &Vector3<T>, gmst_rad: T) -> Vector3<T> {
    teme_to_ecef_matrix(gmst_rad).transpose() * r_ecef
}

/// A TEME state (km, km/s) in ECEF, Vallado 2013 algorithm 24 (`teme2ecef`) without polar
/// motion: `r_ecef = R3(θ) r_teme`, `v_ecef = R3(θ) v_teme − ω⊕ × r_ecef` with
/// ω⊕ = [`EARTH_ROTATION_RADPS`] about z. Returns `(r_ecef_km, v_ecef_kmps)`.
pub fn teme_to_ecef<T: Real>(
    r_teme_km: &Vector3<T>,
    v_teme_kmps: &Vector3<T>,
    gmst_rad: T,
) -> (Vector3<T>, Vector3<T>) {
    let m = teme_to_ecef_matrix(gmst_rad);
    let r_ecef_km = m * r_teme_km;
    let omega = Vector3::new(T::of(0.0), T::of(0.0), T::of(EARTH_ROTATION_RADPS));
    let v_ecef_kmps = m * v_teme_kmps - omega.cross(&r_ecef_km);
    (r_ecef_km, v_ecef_kmps)
}

/// An ECEF state (km, km/s) in TEME, the inverse of [`teme_to_ecef`]:
/// `v_teme = R3(−θ)(v_ecef + ω⊕ × r_ecef)`. Returns `(r_teme_km, v_teme_kmps)`.
pub fn ecef_to_teme<T: Real>(
    r_ecef_km: &Vector3<T>,
    v_ecef_kmps: &Vector3<T>,
    gmst_rad: T,
) -> (Vector3<T>, Vector3<T>) {
    let mt = teme_to_ecef_matrix(gmst_rad).transpose();
    let omega = Vector3::new(T::of(0.0), T::of(0.0), T::of(EARTH_ROTATION_RADPS));
    let v_inertial = v_ecef_kmps + omega.cross(r_ecef_km);
    (mt * r_ecef_km, mt * v_inertial)
}

// ---------------------------------------------------------------------------------------------
// Geodetic WGS-84 ↔ Earth-fixed
// ---------------------------------------------------------------------------------------------

/// Geodetic coordinates on the WGS-84 ellipsoid.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Geodetic<T> {
    /// Geodetic latitude φ, rad, −π/2..=π/2 (positive north).
    pub lat_rad: T,
    /// East longitude λ, rad, −π..=π.
    pub lon_rad: T,
    /// Height above the ellipsoid, km.
    pub alt_km: T,
}

/// WGS-84 geodetic → ECEF position in km (Vallado 2013 eq. 3-14, closed form):
/// ```text
/// N = a / √(1 − e² sin² φ)
/// r = ((N + h) cos φ cos λ, (N + h) cos φ sin λ, (N(1 − e²) + h) sin φ)
/// ```
pub fn geodetic_to_ecef<T: Real>(g: &Geodetic<T>) -> Vector3<T> {
    let a = T::of(WGS84_A_KM);
    let e2 = T::of(WGS84_F * (2.0 - WGS84_F));
    let one = T::of(1.0);
    let (sin_lat, cos_lat) = g.lat_rad.sincos();
    let (sin_lon, cos_lon) = g.lon_rad.sincos();
    // N = a / √(1 − e² sin² φ)
    let n = a / Real::sqrt(one - e2 * sin_lat * sin_lat);
    let rho = (n + g.alt_km) * cos_lat;
    Vector3::new(
        rho * cos_lon,
        rho * sin_lon,
        (n * (one - e2) + g.alt_km) * sin_lat,
    )
}

/// Iterations of Bowring's formula in [`ecef_to_geodetic`] (2 reach the f64 rounding level from
/// the surface to beyond GEO; measured in `tests/frames.rs`).
const BOWRING_ITERATIONS: usize = 2;

/// `(s, c) / √(s² + c²)`, the sine and cosine of `atan2(s, c)` without a trigonometric call;
/// `(0, 1)` for the zero vector.
fn unit2<T: Real>(s: T, c: T) -> (T, T) {
    let h = Real::sqrt(s * s + c * c);
    if h > T::of(0.0) {
        (s / h, c / h)
    } else {
        (T::of(0.0), T::of(1.0))
    }
}

/// ECEF position (km) → WGS-84 geodetic, by Bowring's (1976) iteration on the reduced latitude,
/// a fixed 2 times (Bowring, "Transformation from spatial to geographical
/// coordinates", Survey Review 23(181); see Vallado 2013 §3.4):
/// ```text
/// tan β₀ = a z / (b p)
/// tan φ  = (z + e′² b sin³ β) / (p − e² a cos³ β),   tan β = (b/a) tan φ
/// h = p cos φ + z sin φ − a √(1 − e² sin² φ)
/// ```
/// The sines and cosines come from normalised pairs, so there is no division by zero: on the
/// polar axis `p = 0` gives φ = ±π/2 and λ = 0; the height formula is exact at the poles and on
/// the equator. Measured accuracy (−10…40 000 km height, all latitudes): f64 ≤ 2.3e-8 m; f32
/// ≤ 1.9 m (RMS 0.54 m) in position below 2000 km height, ≤ 2.9e-7·|r| at any height, of the
/// order of the f32 resolution of the input itself (0.5 m at 7000 km)
/// (`cargo test --test frames geodetic -- --nocapture`).
///
/// # Errors
/// [`FrameError::NonFinite`]; [`FrameError::NearCentre`] within [`GEODETIC_MIN_RADIUS_KM`] of
/// the centre.
pub fn ecef_to_geodetic<T: Real>(r_ecef_km: &Vector3<T>) -> Result<Geodetic<T>, FrameError> {
    if !all_finite(r_ecef_km) {
        return Err(FrameError::NonFinite);
    }
    let r = norm(r_ecef_km);
    if !(r >= T::of(GEODETIC_MIN_RADIUS_KM)) {
        return Err(FrameError::NearCentre(r.to_f64() as f32));
    }
    let a = T::of(WGS84_A_KM);
    let b = T::of(WGS84_A_KM * (1.0 - WGS84_F));
    let e2 = T::of(WGS84_F * (2.0 - WGS84_F));
    let ep2 = T::of(WGS84_F * (2.0 - WGS84_F) / ((1.0 - WGS84_F) * (1.0 - WGS84_F)));
    let (x, y, z) = (r_ecef_km.x, r_ecef_km.y, r_ecef_km.z);
    let p = Real::sqrt(x * x + y * y);
    // tan β₀ = a z / (b p)
    let (mut sin_u, mut cos_u) = unit2(a * z, b * p);
    let (mut sin_lat, mut cos_lat) = (sin_u, cos_u);
    for _ in 0..BOWRING_ITERATIONS {
        // tan φ = (z + e′² b sin³ β) / (p − e² a cos³ β)
        (sin_lat, cos_lat) = unit2(
            z + ep2 * b * sin_u * sin_u * sin_u,
            p - e2 * a * cos_u * cos_u * cos_u,
        );
        // tan β = (b / a) tan φ
        (sin_u, cos_u) = unit2(b * sin_lat, a * cos_lat);
    }
    let lat_rad = Real::atan2(sin_lat, cos_lat);
    let lon_rad = Real::atan2(y, x);
    // h = p cos φ + z sin φ − a √(1 − e² sin² φ)
    let alt_km = p * cos_lat + z * sin_lat - a * Real::sqrt(T::of(1.0) - e2 * sin_lat * sin_lat);
    Ok(Geodetic {
        lat_rad,
        lon_rad,
        alt_km,
    })
}

// ---------------------------------------------------------------------------------------------
// NED
// ---------------------------------------------------------------------------------------------

/// The rotation ECEF → local North-East-Down at latitude `lat_rad` and east longitude `lon_rad`:
/// `v_ned = M · v_ecef`; rows are N, E, D in ECEF (Vallado 2013 eq. 3-28 reordered):
/// ```text
/// N = (−sin φ cos λ, −sin φ sin λ,  cos φ)
/// E = (−sin λ,        cos λ,        0    )
/// D = (−cos φ cos λ, −cos φ sin λ, −sin φ)
/// ```
/// With the geodetic latitude, D is the ellipsoid's inward normal; with the geocentric latitude
/// it points to the Earth's centre. Defined everywhere, poles included (at φ = ±90° North is
/// the direction of the meridian λ).
pub fn ecef_to_ned_matrix<T: Real>(lat_rad: T, lon_rad: T) -> Matrix3<T> {
    let (sin_lat, cos_lat) = lat_rad.sincos();
    let (sin_lon, cos_lon) = lon_rad.sincos();
    Matrix3::new(
        -sin_lat * cos_lon,
        -sin_lat * sin_lon,
        cos_lat,
        -sin_lon,
        cos_lon,
        T::of(0.0),
        -cos_lat * cos_lon,
        -cos_lat * sin_lon,
        -sin_lat,
    )
}

/// An ECEF vector in local NED at (`lat_rad`, `lon_rad`), see [`ecef_to_ned_matrix`].
pub fn ecef_to_ned<T: Real>(v_ecef: &Vector3<T>, lat_rad: T, lon_rad: T) -> Vector3<T> {
    ecef_to_ned_matrix(lat_rad, lon_rad) * v_ecef
}

/// A local NED vector at (`lat_rad`, `lon_rad`) in ECEF, see [`ecef_to_ned_matrix`].
pub fn ned_to_ecef<T: Real>(v_ned: &Vector3<T>, lat_rad: T, lon_rad: T) -> Vector3<T> {
    ecef_to_ned_matrix(lat_rad, lon_rad).transpose() * v_ned
}

// ---------------------------------------------------------------------------------------------
// Geocentric spherical
// ---------------------------------------------------------------------------------------------

/// Geocentric spherical coordinates.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Spherical<T> {
    /// Distance from the Earth's centre, km.
    pub r_km: T,
    /// Colatitude θ, rad, 0 (north pole) ..= π.
    pub colat_rad: T,
    /// East longitude (or right ascension, in an inertial frame) φ, rad, −π..=π.
    pub lon_rad: T,
}

/// Spherical → Cartesian position in km: `r (sin θ cos φ, sin θ sin φ, cos θ)` (seed 000
/// eqs. 2.3–2.5 with colatitude). The Cartesian frame is the one in which the angles are measured.
pub fn spherical_to_cartesian<T: Real>(s: &Spherical<T>) -> Vector3<T> {
    let (sin_t, cos_t) = s.colat_rad.sincos();
    let (sin_p, cos_p) = s.lon_rad.sincos();
    Vector3::new(
        s.r_km * sin_t * cos_p,
        s.r_km * sin_t * sin_p,
        s.r_km * cos_t,
    )
}

/// Cartesian position (km) → spherical, with `atan2` only (no division): on the polar axis the
/// colatitude is 0 or π and the longitude 0.
///
/// # Errors
/// [`FrameError::NonFinite`]; [`FrameError::Degenerate`] for the zero vector.
pub fn cartesian_to_spherical<T: Real>(r_km: &Vector3<T>) -> Result<Spherical<T>, FrameError> {
    if !all_finite(r_km) {
        return Err(FrameError::NonFinite);
    }
    let r = norm(r_km);
    if !(r > T::of(0.0)) {
        return Err(FrameError::Degenerate);
    }
    let p = Real::sqrt(r_km.x * r_km.x + r_km.y * r_km.y);
    Ok(Spherical {
        r_km: r,
        colat_rad: Real::atan2(p, r_km.z),
        lon_rad: Real::atan2(r_km.y, r_km.x),
    })
}

/// The rotation Cartesian → local spherical basis at (`colat_rad`, `lon_rad`):
/// `(v_r, v_θ, v_φ) = M · v`; rows are r̂ (outward), θ̂ (southward), φ̂ (eastward):
/// ```text
/// r̂ = (sin θ cos φ, sin θ sin φ,  cos θ)
/// θ̂ = (cos θ cos φ, cos θ sin φ, −sin θ)
/// φ̂ = (−sin φ,       cos φ,        0    )
/// ```
/// Its transpose is seed 000 eq. 7.26 (with Dec = π/2 − θ and RA = φ). Defined at the poles.
pub fn cartesian_to_spherical_matrix<T: Real>(colat_rad: T, lon_rad: T) -> Matrix3<T> {
    let (sin_t, cos_t) = colat_rad.sincos();
    let (sin_p, cos_p) = lon_rad.sincos();
    Matrix3::new(
        sin_t * cos_p,
        sin_t * sin_p,
        cos_t,
        cos_t * cos_p,
        cos_t * sin_p,
        -sin_t,
        -sin_p,
        cos_p,
        T::of(0.0),
    )
}

/// Spherical components `(v_r, v_θ, v_φ)` (outward, southward, eastward) at (`colat_rad`,
/// `lon_rad`) → Cartesian components (seed 000 eq. 7.26; e.g. an IGRF field `(B_r, B_θ, B_φ)` to
/// ECEF with the geographic longitude, or to TEME with `lon + θ_GMST`, eq. 7.27).
pub fn spherical_to_cartesian_components<T: Real>(
    v_rtp: &Vector3<T>,
    colat_rad: T,
    lon_rad: T,
) -> Vector3<T> {
    cartesian_to_spherical_matrix(colat_rad, lon_rad).transpose() * v_rtp
}

/// Cartesian components → spherical components `(v_r, v_θ, v_φ)` at (`colat_rad`, `lon_rad`);
/// inverse of [`spherical_to_cartesian_components`].
pub fn cartesian_to_spherical_components<T: Real>(
    v: &Vector3<T>,
    colat_rad: T,
    lon_rad: T,
) -> Vector3<T> {
    cartesian_to_spherical_matrix(colat_rad, lon_rad) * v
}

// ---------------------------------------------------------------------------------------------
// RSW
// ---------------------------------------------------------------------------------------------

/// The rotation inertial → RSW from a position and velocity in that inertial frame (Vallado
/// 2013 eq. 3-19 / seed 000 §2): `v_rsw = M · v`, rows
/// ```text
/// R̂ = r / |r|,   Ŵ = (r × v) / |r × v|,   Ŝ = Ŵ × R̂
/// ```
/// (Ŝ is along the velocity for a circular orbit).
///
/// # Errors
/// [`FrameError::NonFinite`] (also if the squared norms overflow); [`FrameError::Degenerate`] if
/// `r` or `r × v` is zero, or the angle between `r` and `v` is below 1e-6 rad.
pub fn inertial_to_rsw_matrix<T: Real>(
    r: &Vector3<T>,
    v: &Vector3<T>,
) -> Result<Matrix3<T>, FrameError> {
    if !all_finite(r) || !all_finite(v) {
        return Err(FrameError::NonFinite);
    }
    let h = r.cross(v);
    let r_norm = norm(r);
    let h_norm = norm(&h);
    let v_norm = norm(v);
    let limit = T::of(1e-6) * r_norm * v_norm;
    if !limit.finite() || !h_norm.finite() {
        // Squares overflowed.
        return Err(FrameError::NonFinite);
    }
    if !(r_norm > T::of(0.0)) || !(h_norm > limit) {
        return Err(FrameError::Degenerate);
    }
    let r_hat = r / r_norm;
    let w_hat = h / h_norm;
    let s_hat = w_hat.cross(&r_hat);
    Ok(Matrix3::new(
        r_hat.x, r_hat.y, r_hat.z, s_hat.x, s_hat.y, s_hat.z, w_hat.x, w_hat.y, w_hat.z,
    ))
}
