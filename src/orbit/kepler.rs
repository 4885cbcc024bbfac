//! Two-body (Keplerian) propagator of M. Bonjean, *Progetto AraMiS: … determinazione ed al
//! controllo dell'assetto del satellite* (Politecnico di Torino, 2010; "seed 000"), §4.1,
//! eqs. 4.4–4.13.
//!
//! # Use
//! ```
//! # use acs::{orbit::kepler::{Kepler, MU_THESIS_KM3_S2}, time::TimeSpan, tle::Tle};
//! # fn run(tle: &Tle) -> Result<(), acs::orbit::kepler::KeplerError> {
//! let kepler = Kepler::from_tle(tle, MU_THESIS_KM3_S2)?;
//! let r_km = kepler.propagate(TimeSpan::new(3600, 0)).r_teme_km;
//! # Ok(()) }
//! ```
//! Input: the mean elements of a [`Tle`] (n̄, e, i, Ω, ω, M₀) and the time since the TLE epoch.
//! Output: position and velocity in the frame of the elements (TEME of the TLE epoch, which the
//! thesis calls IJK). The thesis computes no velocity; it is added here from the same geometry
//! (`v_PQW = √(μ/p)·(−sin ν, e + cos ν, 0)`).
//!
//! # Algorithm
//! 1. `n = n̄·2π/86 400` rad/s; `a = (μ/n²)^(1/3)` (eq. 4.9); `p = a(1 − e²)` (eq. 4.10).
//! 2. `M = M₀ + n·Δt` (eq. 4.13), kept as an exact `Phase` and reduced to −π..π.
//! 3. Kepler's equation `M = E − e sin E` by Newton–Raphson (eq. 4.4) from the thesis's first
//!    guess (`E = M − e` for M in −π..0, else `M + e`), to f32 resolution, at most 30 steps.
//! 4. True anomaly from `cos ν = (cos E − e)/(1 − e cos E)`,
//!    `sin ν = sin E·√(1 − e²)/(1 − e cos E)` (eqs. 4.5–4.7; the thesis prints a misplaced root).
//! 5. `r_PQW = p/(1 + e cos ν)·(cos ν, sin ν, 0)` (eq. 4.11), `r = R(Ω, i, ω)·r_PQW` (eq. 4.12).
//!
//! Initialisation (`a`, `p`, the rotation and the rate of M) is in f64: the rate needs the TLE's
//! ten digits of mean motion. Propagation is f32.
//!
//! # Validity and accuracy
//! Unperturbed two-body motion of the TLE's *mean* elements: about 15 km from SGP4 at the epoch
//! and 280 km after 18 h for DTUSAT (note 000 §3.2); use [`super::sgp4`] for real work. Elliptic
//! orbits only (0 ≤ e < 1). Measured against an f64 implementation of the same equations
//! (`cargo test --release --test kepler -- --nocapture`), DTUSAT over ±7 days at 1 min:
//! position error 3.5 m max, 1.0 m RMS; velocity 3.7 mm/s max, 0.9 mm/s RMS; flat in time (the
//! f32 spacing of angles near π, 1.2e-7 rad = 0.9 m at 7200 km, met at M, E and the rotation).
//! The note 000 §3.2 values are reproduced within 1.2 m.
//!
//! # Symbols
//! | name | symbol | meaning |
//! |---|---|---|
//! | `n` | n | mean motion, rad/s |
//! | `a_km`, `p_km` | a, p | semi-major axis, semi-latus rectum |
//! | `e` | e | eccentricity |
//! | `m`, `ecc_anomaly`, `nu` | M, E, ν | mean, eccentric and true anomalies |
//! | `pqw_to_teme` | R(Ω, i, ω) | perifocal → inertial rotation |

use core::fmt;

use super::{split_span, Phase, TemeState};
use crate::fmath;
use crate::linalg::{Mat3, Vec3};
use crate::time::TimeSpan;
use crate::tle::Tle;

/// Earth's gravitational parameter used by the thesis (note 000 §3.1; WGS-84), km³/s².
pub const MU_THESIS_KM3_S2: f64 = 398_600.5;

/// Newton iterations at most.
const MAX_ITERATIONS: usize = 30;
/// Newton tolerance on E, rad: a few f32 ulps of an angle of order π.
const TOLERANCE: f32 = 1.0e-6;

/// Why a Kepler propagator cannot be built from the elements.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum KeplerError {
    /// Eccentricity outside 0..1 (hyperbolic and parabolic orbits are not handled).
    Eccentricity(f32),
    /// Mean motion not positive, rev/day.
    MeanMotion(f32),
    /// Gravitational parameter not positive, km³/s².
    Mu(f32),
    /// An element that is not finite.
    Element(&'static str),
}

impl fmt::Display for KeplerError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Eccentricity(e) => write!(f, "eccentricity {e} outside 0..1"),
            Self::MeanMotion(n) => write!(f, "mean motion {n} rev/day not positive"),
            Self::Mu(mu) => write!(f, "gravitational parameter {mu} km³/s² not positive"),
            Self::Element(name) => write!(f, "element {name} not finite"),
        }
    }
}

/// A two-body propagator for one element set.
#[derive(Clone, Debug, PartialEq)]
pub struct Kepler {
    /// Mean anomaly M₀ + n·Δt, per second.
    mean_anomaly: Phase,
    e: f32,
    a_km: f32,
    /// √(1 − e²).
    beta: f32,
    p_km: f32,
    /// √(μ/p), km/s.
    v_scale_kmps: f32,
    /// R(Ω, i, ω): perifocal (PQW) → inertial.
    pqw_to_teme: Mat3,
}

fn finite(x: f64, name: &'static str) -> Result<f64, KeplerError> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(KeplerError::Element(name))
    }
}

impl Kepler {
    /// A propagator from a TLE's mean elements and a gravitational parameter (km³/s²;
    /// [`MU_THESIS_KM3_S2`] for the thesis's).
    ///
    /// # Errors
    /// [`KeplerError`] for a non-finite element, e outside 0..1, n̄ ≤ 0 or μ ≤ 0.
    pub fn from_tle(tle: &Tle, mu_km3_s2: f64) -> Result<Self, KeplerError> {
        use core::f64::consts::{PI, TAU};
        let deg = PI / 180.0;
        let n_rev_day = finite(tle.mean_motion_rev_per_day, "mean motion")?;
        let e = finite(tle.eccentricity, "eccentricity")?;
        let i = finite(tle.inclination_deg, "inclination")? * deg;
        let raan = finite(tle.raan_deg, "right ascension of the node")? * deg;
        let argp = finite(tle.arg_perigee_deg, "argument of perigee")? * deg;
        let m0 = finite(tle.mean_anomaly_deg, "mean anomaly")? * deg;
        if !(mu_km3_s2 > 0.0 && mu_km3_s2.is_finite()) {
            return Err(KeplerError::Mu(mu_km3_s2 as f32));
        }
        if !(n_rev_day > 0.0) {
            return Err(KeplerError::MeanMotion(n_rev_day as f32));
        }
        if !(e >= 0.0) || e >= 1.0 {
            return Err(KeplerError::Eccentricity(e as f32));
        }
        // n = n̄·2π/86 400 rad/s; a = (μ/n²)^(1/3) (eq. 4.9); p = a(1 − e²) (eq. 4.10)
        let n = n_rev_day * TAU / 86_400.0;
        let a_km = libm::cbrt(mu_km3_s2 / (n * n));
        let p_km = a_km * (1.0 - e * e);
        let (so, co) = (libm::sin(raan), libm::cos(raan));
        let (sw, cw) = (libm::sin(argp), libm::cos(argp));
        let (si, ci) = (libm::sin(i), libm::cos(i));
        // R(Ω, i, ω) = R3(−Ω)·R1(−i)·R3(−ω) (eq. 4.12)
        let pqw_to_teme = Mat3::new(
            (co * cw - so * sw * ci) as f32,
            (-co * sw - so * cw * ci) as f32,
            (so * si) as f32,
            (so * cw + co * sw * ci) as f32,
            (-so * sw + co * cw * ci) as f32,
            (-co * si) as f32,
            (sw * si) as f32,
            (cw * si) as f32,
            ci as f32,
        );
        Ok(Self {
            mean_anomaly: Phase::new(m0, n),
            e: e as f32,
            a_km: a_km as f32,
            beta: libm::sqrt(1.0 - e * e) as f32,
            p_km: p_km as f32,
            v_scale_kmps: libm::sqrt(mu_km3_s2 / p_km) as f32,
            pqw_to_teme,
        })
    }

    /// The semi-major axis `a = (μ/n²)^(1/3)` (eq. 4.9), km.
    pub fn semi_major_axis_km(&self) -> f32 {
        self.a_km
    }

    /// Position and velocity `since_epoch` after the TLE epoch, in the frame of the elements.
    pub fn propagate(&self, since_epoch: TimeSpan) -> TemeState {
        let (whole_s, frac_s) = split_span(since_epoch, 1);
        // M = M₀ + n·Δt (eq. 4.13), in −π..π
        let m = self.mean_anomaly.radians(whole_s, frac_s);
        let ecc_anomaly = solve_kepler(m, self.e);
        let (sin_e, cos_e) = fmath::sincos(ecc_anomaly);
        // eqs. 4.5–4.7
        let denom = 1.0 - self.e * cos_e;
        let cos_nu = (cos_e - self.e) / denom;
        let sin_nu = sin_e * self.beta / denom;
        // eq. 4.11
        let r = self.p_km / (1.0 + self.e * cos_nu);
        let r_pqw = Vec3::new(r * cos_nu, r * sin_nu, 0.0);
        let v_pqw = Vec3::new(-sin_nu, self.e + cos_nu, 0.0) * self.v_scale_kmps;
        TemeState {
            r_teme_km: self.pqw_to_teme * r_pqw,
            v_teme_kmps: self.pqw_to_teme * v_pqw,
        }
    }
}

/// Solves `M = E − e sin E` for E (eq. 4.4) by Newton–Raphson from the thesis's first guess.
/// `m` in −π..π, `0 ≤ e < 1`; at most 30 steps.
pub fn solve_kepler(m: f32, e: f32) -> f32 {
    // thesis: E₀ = M − e if M ∈ (−π, 0) or M > π, else M + e
    let mut ecc_anomaly =
        if (m > -core::f32::consts::PI && !(m >= 0.0)) || m > core::f32::consts::PI {
            m - e
        } else {
            m + e
        };
    for _ in 0..MAX_ITERATIONS {
        let (s, c) = fmath::sincos(ecc_anomaly);
        let step = (m - ecc_anomaly + e * s) / (1.0 - e * c);
        ecc_anomaly += step;
        if !(fmath::abs(step) >= TOLERANCE) {
            break;
        }
    }
    ecc_anomaly
}
