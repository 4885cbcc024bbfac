//! SGP4, near-Earth: the NORAD analytical propagator as revised by Vallado, Crawford, Hujsak and
//! Kelso, "Revisiting Spacetrack Report #3", AIAA 2006-6753 (its `sgp4init`/`sgp4` routines), with
//! the equations as that paper and its code give them. Seed 000 (Bonjean's AraMiS ACS thesis) §4.3 ran the
//! same code, all in `float`, on the MSP430.
//!
//! # Use
//! ```
//! # use acs::{orbit::sgp4::{Gravity, Sgp4}, time::TimeSpan, tle::Tle};
//! # fn run(tle: &Tle) -> Result<(), acs::orbit::sgp4::Sgp4Error> {
//! let sgp4 = Sgp4::new(tle, Gravity::Wgs72)?;
//! let state = sgp4.propagate(TimeSpan::new(3600, 0))?; // one hour after the TLE epoch
//! let r_teme_km = state.r_teme_km;
//! # Ok(()) }
//! ```
//! Input: a parsed [`Tle`] and the time since its epoch as a [`TimeSpan`] (or an f32 split pair,
//! [`Sgp4::propagate_split`]). Output: [`TemeState`], position (km) and velocity (km/s) in the TEME
//! frame of date.
//!
//! # Precision
//! - **Initialisation in double-f32 where it matters, f32 elsewhere; no f64 arithmetic**
//!   ([`Sgp4::new`], once per element set). The secular rates need the TLE's ten significant
//!   digits of mean motion (f32 keeps seven: 6e-8 of 300 rad of mean anomaly after three days is
//!   130 m) and cos i₀ beyond f32 (~2 m a week): the un-Kozai'd mean motion, a₀″, cos i₀ and the
//!   rates Ṁ, ω̇, Ω̇ are computed as unevaluated sums of two f32 (`dfloat`, Dekker's algorithms,
//!   ~48 bits), and so are the drag reference quantities (a₀″ − s, 1 − η², where low perigees
//!   cancel) and C₁ (its t² term reaches radians on a decaying orbit: in f32, case 22312 moves
//!   from 1.9 m to 2.9 m). The other coefficients multiply small terms and are f32. The TLE's
//!   f64 fields are split into two f32 from their bits (integer operations), so the MSP430 build
//!   pulls no f64 soft float and no f64 `libm`. Everything is then stored in f32.
//! - **Propagation in f32**, with the `crate::fmath` functions, except for the secular angles
//!   (mean anomaly, argument of perigee, node and their sum), which are `Phase`s: exact
//!   fixed-point turns advanced by 64-bit integer products for the whole minutes, f32 only for the
//!   sub-minute remainder and the small periodic terms. Angles are reduced to −π..π (not 0..2π),
//!   which halves the f32 spacing of the argument of latitude.
//! - Kepler's equation is solved to f32 resolution and the sine and cosine of the solution are
//!   corrected to first order for the last Newton step (Vallado uses those of the previous
//!   iterate, harmless with his 1e-12 tolerance in f64 but not with an f32 tolerance).
//!
//! # Accuracy (measured, `cargo test --release --test sgp4 -- --nocapture`)
//! Against the f64 Vallado reference files of `tests/data/sgp4/` (per-file figures in the
//! `docs/accuracy.md`), position / velocity error:
//! - the 9 near-Earth cases of `SGP4-VER.TLE` over their listed times: 3.2 m / 3.5 mm/s max
//!   (RMS 1.3 m / 1.4 mm/s);
//! - the 12 `sat900xx` element sets from −1 to +3 days: 4.9 m / 4.8 mm/s max (RMS 1.2 m);
//! - DTUSAT over 7 days, WGS-72 and WGS-84: 4.7 m / 5.0 mm/s max (RMS 1.4 m).
//!
//! The error does not grow with time (it is the f32 spacing of angles near π, 1.2e-7 rad, met a
//! few times per evaluation). The same code with every value f32 (the thesis's port) is 205 m,
//! 529 m and 868 m off on the same three sets. Test bounds: 20 m, 20 m, 100 m.
//!
//! # Cost on the MSP430 (measured, `firmware/msp430-bench --groups sgp4`)
//! Without the hardware multiplier (with it): initialisation 1 225 605 (1 125 281) cycles, once
//! per element set; propagation 121 845 (102 303) cycles, budget 150 000. Code (opt-level "s",
//! flight image with the ACS loop): [`Sgp4::new`] ≈ 7.4 KB, propagation 4.9 KB, double-f32
//! kernels and phases 2.9 KB. The double-f32 operators take their operands by reference and are
//! not inlined on the MSP430 (`dfloat`), which made the initialisation 5.9 KB smaller than the
//! inlined form with the same operations in the same order: results are bit for bit unchanged.
//!
//! # Initialisation on the ground
//! [`Sgp4::to_words`] writes the initialised element set as [`ELEMENT_WORDS`] 32-bit words (a
//! format tag, the epoch, the constants and phases, a checksum: 232 B to uplink) and
//! [`Sgp4::from_words`] reads them back, checked, on board: propagation is then bit for bit that
//! of the element set that wrote them (`tests/sgp4.rs`, every near-Earth set of the reference
//! files), and the board needs neither the TLE parser nor [`Sgp4::new`]: the flight image
//! without them is 11.8 KB smaller (the flight image; with `Sgp4::new` on board, firmware feature
//! `onboard-init`: `firmware/tools/loop-image s onboard-init`).
//!
//! # Validity and errors
//! Near-Earth element sets only (un-Kozai'd period below 225 min); a deep-space set gives
//! [`Sgp4Error::DeepSpace`] at initialisation. Vallado's error codes map to [`Sgp4Error`]:
//! 1 → [`Sgp4Error::Eccentricity`], 2 → [`Sgp4Error::MeanMotion`],
//! 4 → [`Sgp4Error::SemiLatusRectum`], 5 → [`Sgp4Error::SubOrbital`], 6 → [`Sgp4Error::Decayed`]
//! (3 concerns the deep-space perturbations only). Vallado's 2006 code no longer raises error 5
//! for a perigee below the surface at epoch (its decay check covers it, and verification case
//! 28872 propagates for 50 min from such elements); here it is raised when the whole mean orbit,
//! apogee included, is below the surface, which the decay check would report at any time.
//! Propagation never panics: non-finite times give [`Sgp4Error::Time`], and a result that is not
//! finite (the drag polynomial far outside its range) gives [`Sgp4Error::Diverged`].
//!
//! # Source layout
//! `sgp4/init.rs`: [`Sgp4::new`]; `sgp4/propagate.rs`: [`Sgp4::propagate`] and
//! [`Sgp4::propagate_split`]; `sgp4/words.rs`: [`Sgp4::to_words`], [`Sgp4::from_words`],
//! [`words_checksum`]; this file: the types, the gravity models and the errors.
//!
//! # Symbols (Vallado's names, note 000 §3.3)
//! | name | symbol | meaning |
//! |---|---|---|
//! | `no` | n₀″ | un-Kozai'd (Brouwer) mean motion, rad/min |
//! | `ao` | a₀″ | semi-major axis at epoch, Earth radii (ER) |
//! | `ecco`, `inclo`, `argpo`, `nodeo`, `mo` | e₀, i₀, ω₀, Ω₀, M₀ | mean elements at epoch |
//! | `mdot`, `argpdot`, `nodedot` | Ṁ, ω̇, Ω̇ | secular rates, rad/min |
//! | `cc1`…`cc5`, `d2`…`d4` | C₁…C₅, D₂…D₄ | drag coefficients |
//! | `t2cof`…`t5cof` | | mean-longitude drag polynomial |
//! | `isimp` | | simplified drag for perigee below 220 km |
//! | `am`, `em`, `nm` | a, e, n | drag-perturbed mean elements at `t` |
//! | `axnl`, `aynl` | a_xN, a_yN | long-period eccentricity vector |
//! | `eo1` | E + ω | solution of Kepler's equation |
//! | `mrt`, `su`, `xnode`, `xinc` | r_k, u_k, Ω_k, i_k | short-period corrected radius and angles |

use core::fmt;

#[cfg(doc)]
use super::TemeState;
use super::{Df, Phase};
#[cfg(doc)]
use crate::time::TimeSpan;
#[cfg(doc)]
use crate::tle::Tle;

mod init;
mod propagate;
mod words;

pub use words::{words_checksum, ELEMENT_WORDS};

/// Earth gravity model of the propagator (Vallado's `getgravconst`).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Gravity {
    /// WGS-72, the model TLEs are fitted with (default).
    #[default]
    Wgs72,
    /// WGS-84, the thesis's choice (seed 000 §4.3; note 000 §0.2).
    Wgs84,
}

/// The constants of a [`Gravity`] model, as Vallado's `getgravconst` gives them, in double-f32
/// (built by the compiler from the f64 values; no f64 arithmetic at run time).
#[derive(Copy, Clone, Debug, PartialEq)]
struct GravityConstants {
    /// Earth radius, km.
    radius_km: Df,
    /// √(μ/R³) in ER^1.5 per minute.
    xke: Df,
    /// Zonal harmonics.
    j2: Df,
    j3: Df,
    j4: Df,
}

impl GravityConstants {
    /// `xke` is `60/√(R³/μ)` evaluated in f64 (checked by a unit test), written out because
    /// `sqrt` is not available to the compiler's constant evaluation.
    const fn new(radius_km: f64, xke: f64, j2: f64, j3: f64, j4: f64) -> Self {
        Self {
            radius_km: Df::from_f64_const(radius_km),
            xke: Df::from_f64_const(xke),
            j2: Df::from_f64_const(j2),
            j3: Df::from_f64_const(j3),
            j4: Df::from_f64_const(j4),
        }
    }
}

/// μ (km³/s²), R (km), J₂, J₃, J₄ of WGS-72.
const WGS72: (f64, f64, f64, f64, f64) = (
    398_600.8,
    6378.135,
    0.001_082_616,
    -0.000_002_538_81,
    -0.000_001_655_97,
);
/// μ (km³/s²), R (km), J₂, J₃, J₄ of WGS-84.
const WGS84: (f64, f64, f64, f64, f64) = (
    398_600.5,
    6378.137,
    0.001_082_629_989_05,
    -0.000_002_532_153_06,
    -0.000_001_610_987_61,
);

impl Gravity {
    fn constants(self) -> GravityConstants {
        const C72: GravityConstants =
            GravityConstants::new(WGS72.1, 0.074_366_916_133_173_42, WGS72.2, WGS72.3, WGS72.4);
        const C84: GravityConstants =
            GravityConstants::new(WGS84.1, 0.074_366_853_168_713_85, WGS84.2, WGS84.3, WGS84.4);
        match self {
            Self::Wgs72 => C72,
            Self::Wgs84 => C84,
        }
    }
}

/// Why an element set cannot be propagated (Vallado's error codes, plus the cases this crate
/// refuses rather than propagates wrongly). Times are minutes since the TLE epoch.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Sgp4Error {
    /// Vallado error 1: eccentricity outside 0..1 at epoch, or the drag-perturbed mean
    /// eccentricity outside −0.001..1 at `tsince_min`.
    Eccentricity {
        /// The offending eccentricity.
        eccentricity: f32,
        /// Minutes since epoch (0 at initialisation).
        tsince_min: f32,
    },
    /// Vallado error 2: mean motion (Kozai or un-Kozai'd) not positive or not finite, rad/min.
    MeanMotion {
        /// The offending mean motion, rad/min.
        rad_per_min: f32,
    },
    /// Vallado error 4: negative semi-latus rectum at `tsince_min`.
    SemiLatusRectum {
        /// Minutes since epoch.
        tsince_min: f32,
    },
    /// Vallado error 5 (see the module doc): the whole mean orbit at epoch is below the surface.
    SubOrbital {
        /// Mean apogee altitude at epoch, km (negative).
        apogee_km: f32,
    },
    /// Vallado error 6: the satellite has decayed (radius below one Earth radius).
    Decayed {
        /// Minutes since epoch.
        tsince_min: f32,
        /// Radius at that time, km.
        radius_km: f32,
    },
    /// A deep-space element set (period of 225 min or more): SDP4 is not implemented.
    DeepSpace {
        /// Un-Kozai'd period, minutes.
        period_min: f32,
    },
    /// An element that is not finite, or an inclination outside 0..180°.
    Element {
        /// Which element.
        field: &'static str,
    },
    /// The time since epoch is not finite or beyond ±10⁹ min.
    Time {
        /// The offending value, minutes.
        tsince_min: f32,
    },
    /// The result is not finite: the drag polynomials diverged (far outside the element set's
    /// validity).
    Diverged {
        /// Minutes since epoch.
        tsince_min: f32,
    },
    /// Initialised elements ([`Sgp4::from_words`]) with a wrong format tag or checksum, or a
    /// word out of its range; carries the index of the first bad word.
    Words {
        /// Index of the offending word.
        index: u8,
    },
}

impl fmt::Display for Sgp4Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Eccentricity {
                eccentricity,
                tsince_min,
            } => write!(
                f,
                "eccentricity {eccentricity} out of range at {tsince_min} min (SGP4 error 1)"
            ),
            Self::MeanMotion { rad_per_min } => {
                write!(
                    f,
                    "mean motion {rad_per_min} rad/min not positive (SGP4 error 2)"
                )
            }
            Self::SemiLatusRectum { tsince_min } => write!(
                f,
                "negative semi-latus rectum at {tsince_min} min (SGP4 error 4)"
            ),
            Self::SubOrbital { apogee_km } => write!(
                f,
                "sub-orbital element set: mean apogee altitude {apogee_km} km (SGP4 error 5)"
            ),
            Self::Decayed {
                tsince_min,
                radius_km,
            } => write!(
                f,
                "satellite decayed at {tsince_min} min: radius {radius_km} km (SGP4 error 6)"
            ),
            Self::DeepSpace { period_min } => write!(
                f,
                "deep-space element set (period {period_min} min ≥ 225 min): not supported"
            ),
            Self::Element { field } => write!(f, "element {field} not finite or out of range"),
            Self::Time { tsince_min } => {
                write!(
                    f,
                    "time since epoch {tsince_min} min not finite or too large"
                )
            }
            Self::Diverged { tsince_min } => write!(
                f,
                "propagation diverged at {tsince_min} min (far outside the element set's validity)"
            ),
            Self::Words { index } => {
                write!(f, "initialised SGP4 elements: word {index} is invalid")
            }
        }
    }
}

/// Drag terms used only when the perigee is above 220 km (`isimp = 0`).
#[derive(Copy, Clone, Debug, PartialEq)]
struct FullDrag {
    d2: f32,
    d3: f32,
    d4: f32,
    t3cof: f32,
    t4cof: f32,
    t5cof: f32,
    cc5: f32,
    omgcof: f32,
    xmcof: f32,
    eta: f32,
    delmo: f32,
    sinmao: f32,
}

impl FullDrag {
    /// All terms zero (the words of an element set without them).
    const ZERO: Self = Self {
        d2: 0.0,
        d3: 0.0,
        d4: 0.0,
        t3cof: 0.0,
        t4cof: 0.0,
        t5cof: 0.0,
        cc5: 0.0,
        omgcof: 0.0,
        xmcof: 0.0,
        eta: 0.0,
        delmo: 0.0,
        sinmao: 0.0,
    };
}

/// An initialised near-Earth SGP4 propagator for one element set (Vallado's `elsetrec`).
///
/// Immutable after [`Sgp4::new`]: propagation is a pure function of the time since epoch.
#[derive(Clone, Debug, PartialEq)]
pub struct Sgp4 {
    /// Epoch of the elements (UTC).
    epoch: crate::time::Epoch<crate::time::Utc>,
    radius_km: f32,
    xke: f32,
    j2: f32,
    /// a₀″ in km, rounded once (the radius scale of the result: storing a₀″ in ER and R_E
    /// separately would round twice, a radial bias of up to 1 m).
    ao_km: f32,
    /// R_E·kₑ/60, ER/min → km/s.
    v_scale_kmps: f32,
    /// Mean anomaly M₀ + Ṁt.
    mean_anomaly: Phase,
    /// Argument of perigee ω₀ + ω̇t.
    arg_perigee: Phase,
    /// Node Ω₀ + Ω̇t.
    node: Phase,
    /// Mean argument of latitude (M₀ + ω₀) + (Ṁ + ω̇)t.
    arg_latitude: Phase,
    no: f32,
    ao: f32,
    ecco: f32,
    bstar: f32,
    cosio: f32,
    sinio: f32,
    con41: f32,
    x1mth2: f32,
    x7thm1: f32,
    cc1: f32,
    cc4: f32,
    nodecf: f32,
    t2cof: f32,
    xlcof: f32,
    aycof: f32,
    /// `None` when `isimp = 1` (perigee below 220 km).
    full_drag: Option<FullDrag>,
}

/// Whether an f32 is finite, from its bits (no comparison helper, NaN-safe on the MSP430).
fn finite32(x: f32) -> bool {
    x.to_bits() & 0x7f80_0000 != 0x7f80_0000
}

impl Sgp4 {
    /// The epoch of the element set (UTC).
    pub fn epoch(&self) -> crate::time::Epoch<crate::time::Utc> {
        self.epoch
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn xke_is_vallados_f64_value() {
        for (g, (mu, r, ..)) in [(Gravity::Wgs72, WGS72), (Gravity::Wgs84, WGS84)] {
            let xke = 60.0 / libm::sqrt(r * r * r / mu);
            let c = g.constants();
            let got = f64::from(c.xke.hi()) + f64::from(c.xke.lo());
            assert!((got - xke).abs() < 1e-16, "{g:?}: {got} vs {xke}");
        }
    }
}
