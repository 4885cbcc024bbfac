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

use super::{split_span, Df, Phase, TemeState};
use crate::fmath;
use crate::linalg::Vec3;
use crate::time::TimeSpan;
use crate::tle::Tle;

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

/// Largest |time since epoch| accepted by [`Sgp4::propagate_split`], minutes.
const MAX_TSINCE_MIN: f32 = 1.0e9;
/// Newton tolerance of Kepler's equation: a few f32 ulps of an angle of order π.
const KEPLER_TOLERANCE: f32 = 1.0e-6;
/// Newton iterations at most (Vallado's cap).
const KEPLER_MAX_ITERATIONS: usize = 10;
/// Vallado's near-Earth limit: period below 225 min.
const DEEP_SPACE_PERIOD_MIN: f32 = 225.0;

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

/// A TLE field as double-f32 (its f64 bits split with integer operations).
fn element(x: f64, field: &'static str) -> Result<Df, Sgp4Error> {
    Df::from_f64(x).ok_or(Sgp4Error::Element { field })
}

/// Whether an f32 is finite, from its bits (no comparison helper, NaN-safe on the MSP430).
fn finite32(x: f32) -> bool {
    x.to_bits() & 0x7f80_0000 != 0x7f80_0000
}

/// cos of an angle in degrees, 0 ≤ x ≤ 180, in double length: sin(90° − x) (the subtraction in
/// degrees is exact), by its Taylor series.
fn cos_degrees(x_deg: &Df) -> Df {
    const DEG: Df = Df::from_f64_const(core::f64::consts::PI / 180.0);
    (&(90.0 - x_deg) * &DEG).sin_pi_2()
}

/// sin and cos (f32) of an angle given in degrees (double-f32, any finite value): reduced
/// modulo 360° in double length, then `fmath::sincos`.
fn sincos_degrees(x_deg: &Df) -> (f32, f32) {
    let r = turns_of_degrees(x_deg);
    let r = &r - crate::fmath::floor(r.hi());
    crate::fmath::sincos(r.to_f32() * core::f32::consts::TAU)
}

/// A TLE angle in degrees as turns, modulo one turn (double-f32).
fn turns_of_degrees(x_deg: &Df) -> Df {
    let turns = x_deg / 360.0;
    &turns - crate::fmath::floor(turns.hi())
}

impl Sgp4 {
    /// Initialises the propagator from an element set (Vallado's `twoline2rv` conversions,
    /// `initl` and `sgp4init`, near-Earth part), then checks it by propagating to the epoch as
    /// Vallado's `sgp4init` does.
    ///
    /// f32 and double-f32 operations only (module docs, "Precision"): no f64 arithmetic, so
    /// the MSP430 build carries no f64 soft float. The TLE's f64 fields are split into
    /// double-f32 from their bits.
    ///
    /// # Errors
    /// [`Sgp4Error::Element`] for a non-finite element (or one beyond the f32 range),
    /// [`Sgp4Error::Eccentricity`] outside 0..1, [`Sgp4Error::MeanMotion`],
    /// [`Sgp4Error::DeepSpace`], [`Sgp4Error::SubOrbital`], or any error of the propagation to
    /// the epoch.
    pub fn new(tle: &Tle, gravity: Gravity) -> Result<Self, Sgp4Error> {
        /// rev/day → rad/min: 2π/1440.
        const REV_PER_DAY: Df = Df::from_f64_const(core::f64::consts::TAU / 1440.0);
        /// rad → turns.
        const INV_TAU: Df = Df::from_f64_const(1.0 / core::f64::consts::TAU);
        /// 1/3.
        const X1O3: Df = Df::from_f64_const(1.0 / 3.0);
        let g = gravity.constants();
        let radius_km = g.radius_km;
        // twoline2rv: rev/day → rad/min, degrees → rad (angles kept in degrees here)
        let n_rev_day = element(tle.mean_motion_rev_per_day, "mean motion")?;
        let ecco = element(tle.eccentricity, "eccentricity")?;
        let inclo_deg = element(tle.inclination_deg, "inclination")?;
        let nodeo_deg = element(tle.raan_deg, "right ascension of the node")?;
        let argpo_deg = element(tle.arg_perigee_deg, "argument of perigee")?;
        let mo_deg = element(tle.mean_anomaly_deg, "mean anomaly")?;
        let bstar = element(tle.bstar, "B*")?;
        // 0 ≤ i ≤ 180°, on hi + lo
        let (ih, il) = (inclo_deg.hi(), inclo_deg.lo());
        let above_0 = ih > 0.0 || (ih == 0.0 && il >= 0.0);
        let below_180 = !(ih >= 180.0) || (ih == 180.0 && !(il > 0.0));
        if !(above_0 && below_180) {
            return Err(Sgp4Error::Element {
                field: "inclination",
            });
        }
        let no_kozai = &n_rev_day * &REV_PER_DAY;
        if !(no_kozai.hi() > 0.0) {
            return Err(Sgp4Error::MeanMotion {
                rad_per_min: no_kozai.to_f32(),
            });
        }
        if !(ecco.hi() >= 0.0) || ecco.hi() >= 1.0 {
            return Err(Sgp4Error::Eccentricity {
                eccentricity: ecco.to_f32(),
                tsince_min: 0.0,
            });
        }

        // initl: recover the un-Kozai'd mean motion
        // (double-f32 operators take references: see `dfloat`)
        let eccsq = &ecco * &ecco;
        let omeosq = 1.0 - &eccsq;
        let rteosq = omeosq.sqrt();
        let cosio = cos_degrees(&inclo_deg);
        let cosio2 = &cosio * &cosio;
        // (in a block: its temporaries leave the stack frame, ≈ 100 B on the MSP430)
        let no = {
            let ak = two_thirds_power(&(&g.xke / &no_kozai));
            // d1 = 0.75·J₂·(3cos²i₀ − 1)/(√(1 − e₀²)·(1 − e₀²))
            let d1 = &(&(0.75 * &g.j2) * &(&(3.0 * &cosio2) - 1.0)) / &(&rteosq * &omeosq);
            let del = &d1 / &(&ak * &ak);
            // adel = ak·(1 − δ² − δ·(1/3 + 134δ²/81))
            let del2 = &del * &del;
            let series = &X1O3 + &(&(&(134.0 * &del) * &del) / 81.0);
            let adel = &ak * &(&(1.0 - &del2) - &(&del * &series));
            let del = &d1 / &(&adel * &adel);
            &no_kozai / &(1.0 + &del)
        };
        if !(finite32(no.hi()) && no.hi() > 0.0) {
            return Err(Sgp4Error::MeanMotion {
                rad_per_min: no.to_f32(),
            });
        }
        let period_min = core::f32::consts::TAU / no.to_f32();
        if period_min >= DEEP_SPACE_PERIOD_MIN {
            return Err(Sgp4Error::DeepSpace { period_min });
        }
        let ao = two_thirds_power(&(&g.xke / &no));
        let alta = &(&ao * &(1.0 + &ecco)) - 1.0;
        if !(alta.hi() >= 0.0) {
            return Err(Sgp4Error::SubOrbital {
                apogee_km: (&alta * &radius_km).to_f32(),
            });
        }

        // sgp4init, secular rates (double-f32: they multiply the time, up to 10⁴ min a week)
        let po = &ao * &omeosq;
        let pinvsq = 1.0 / &(&po * &po);
        let con42 = 1.0 - &(5.0 * &cosio2);
        let con41 = &(&-&con42 - &cosio2) - &cosio2;
        let temp1 = &(&(1.5 * &g.j2) * &pinvsq) * &no;
        let xhdot1 = &-&temp1 * &cosio;
        // the O(J₂²) and J₄ terms, 10⁻⁶ of n₀″, in f32 (below 10⁻¹³ rad/min)
        let (c2, no32, pinvsq32) = (cosio2.to_f32(), no.to_f32(), pinvsq.to_f32());
        let c4 = c2 * c2;
        let temp2 = 0.5 * temp1.to_f32() * g.j2.to_f32() * pinvsq32;
        let temp3 = -0.46875 * g.j4.to_f32() * pinvsq32 * pinvsq32 * no32;
        let rteosq32 = rteosq.to_f32();
        let mdot = &(&no + &(&(&(0.5 * &temp1) * &rteosq) * &con41))
            + 0.0625 * temp2 * rteosq32 * (13.0 - 78.0 * c2 + 137.0 * c4);
        let argpdot = &(&(-0.5 * &temp1) * &con42)
            + (0.0625 * temp2 * (7.0 - 114.0 * c2 + 395.0 * c4)
                + temp3 * (3.0 - 36.0 * c2 + 49.0 * c4));
        let nodedot = &xhdot1
            + (0.5 * temp2 * (4.0 - 19.0 * c2) + 2.0 * temp3 * (3.0 - 7.0 * c2)) * cosio.to_f32();

        // drag reference height and the perigee-relative quantities, double-f32: a − s and
        // 1 − η² cancel for low perigees (f32 there puts 22312 160 m off)
        // (in a block, returning f32: its double-f32 temporaries leave the stack frame)
        let (isimp, sfour, tsi, eta, etasq, eeta, psisq, coef, coef1, cc1) = {
            let rp = &ao * &(1.0 - &ecco);
            let isimp = !((&rp - &(&(220.0 / &radius_km) + 1.0)).hi() >= 0.0);
            let perige = &(&rp - 1.0) * &radius_km;
            let (sfour, qzms24) = if !(perige.hi() >= 156.0) {
                let s = if !(perige.hi() >= 98.0) {
                    Df::from_f32(20.0)
                } else {
                    &perige - 78.0
                };
                (
                    &(&s / &radius_km) + 1.0,
                    fourth_power(&(&(120.0 - &s) / &radius_km)),
                )
            } else {
                (
                    &(78.0 / &radius_km) + 1.0,
                    fourth_power(&((120.0 - 78.0) / &radius_km)),
                )
            };
            let tsi = 1.0 / &(&ao - &sfour);
            let eta = &(&ao * &ecco) * &tsi;
            let etasq = &eta * &eta;
            let eeta = &ecco * &eta;
            let psisq = (1.0 - &etasq).to_f32();
            let psisq = Df::from_f32(fmath::abs(psisq)); // |1 − η²|
            let coef = &qzms24 * &fourth_power(&tsi);
            // C₁ = B*·C₂ scales the mean-longitude drag t²·(3/2)C₁ (radians after a day for a
            // decaying orbit): double-f32 too. psisq^3.5 as psisq³·√psisq.
            let coef1 = &coef / &(&(&(&psisq * &psisq) * &psisq) * &psisq.sqrt());
            // C₂ = coef1·n₀″·(a₀″(1 + 1.5η² + eη(4 + η²)) + 0.375J₂·ξ/ψ²·con41·(8 + 3η²(8 + η²)))
            let a_term = &ao * &(&(1.0 + &(1.5 * &etasq)) + &(&eeta * &(4.0 + &etasq)));
            let j2_term = &(&(&(&(0.375 * &g.j2) * &tsi) / &psisq) * &con41)
                * &(8.0 + &(&(3.0 * &etasq) * &(8.0 + &etasq)));
            let cc2 = &(&coef1 * &no) * &(&a_term + j2_term.to_f32());
            let cc1 = (&bstar * &cc2).to_f32();
            (
                isimp,
                sfour.to_f32(),
                tsi.to_f32(),
                eta.to_f32(),
                etasq.to_f32(),
                eeta.to_f32(),
                psisq.to_f32(),
                coef.to_f32(),
                coef1.to_f32(),
                cc1,
            )
        };

        // sgp4init, drag and periodic coefficients: f32 (they multiply small terms)
        let re = radius_km.to_f32();
        let j2 = g.j2.to_f32();
        let j3oj2 = (&g.j3 / &g.j2).to_f32();
        let ao_km = (&ao * &radius_km).to_f32();
        let one_plus_cosio = (&cosio + 1.0).to_f32(); // no cancellation near i₀ = 180°
        let (ao, ecco, bstar) = (ao.to_f32(), ecco.to_f32(), bstar.to_f32());
        let (cosio, omeosq, con41) = (cosio.to_f32(), omeosq.to_f32(), con41.to_f32());
        let sinio = fmath::sqrt(fmath::abs((1.0 - &cosio2).to_f32())); // ≥ 0 for 0 ≤ i₀ ≤ 180°
        let large_ecc = ecco > 1.0e-4;
        let cc3 = if large_ecc {
            -2.0 * coef * tsi * j3oj2 * no32 * sinio / ecco
        } else {
            0.0
        };
        let x1mth2 = 1.0 - c2;
        let (sin_argpo, cos_argpo) = sincos_degrees(&argpo_deg);
        let cos_2argpo = 1.0 - 2.0 * sin_argpo * sin_argpo;
        let cc4 = 2.0
            * no32
            * coef1
            * ao
            * omeosq
            * (eta * (2.0 + 0.5 * etasq) + ecco * (0.5 + 2.0 * etasq)
                - j2 * tsi / (ao * psisq)
                    * (-3.0 * con41 * (1.0 - 2.0 * eeta + etasq * (1.5 - 0.5 * eeta))
                        + 0.75 * x1mth2 * (2.0 * etasq - eeta * (1.0 + etasq)) * cos_2argpo));
        let cc5 = 2.0 * coef1 * ao * omeosq * (1.0 + 2.75 * (etasq + eeta) + eeta * etasq);
        let omgcof = bstar * cc3 * cos_argpo;
        let xmcof = if large_ecc {
            -2.0 / 3.0 * coef * bstar / eeta
        } else {
            0.0
        };
        let nodecf = 3.5 * omeosq * xhdot1.to_f32() * cc1;
        let t2cof = 1.5 * cc1;
        // Vallado's guard against division by zero at i = 180°
        let one_plus_cosio = if fmath::abs(one_plus_cosio) > 1.5e-12 {
            one_plus_cosio
        } else {
            1.5e-12
        };
        let xlcof = -0.25 * j3oj2 * sinio * (3.0 + 5.0 * cosio) / one_plus_cosio;
        let aycof = -0.5 * j3oj2 * sinio;
        let (sinmao, cos_mo) = sincos_degrees(&mo_deg);
        let delmo = cube(1.0 + eta * cos_mo);
        let x7thm1 = 7.0 * c2 - 1.0;
        let full_drag = if isimp {
            None
        } else {
            let cc1sq = cc1 * cc1;
            let d2 = 4.0 * ao * tsi * cc1sq;
            let temp = d2 * tsi * cc1 / 3.0;
            let d3 = (17.0 * ao + sfour) * temp;
            let d4 = 0.5 * temp * ao * tsi * (221.0 * ao + 31.0 * sfour) * cc1;
            Some(FullDrag {
                d2,
                d3,
                d4,
                t3cof: d2 + 2.0 * cc1sq,
                t4cof: 0.25 * (3.0 * d3 + cc1 * (12.0 * d2 + 10.0 * cc1sq)),
                t5cof: 0.2
                    * (3.0 * d4
                        + 12.0 * cc1 * d3
                        + 6.0 * d2 * d2
                        + 15.0 * cc1sq * (2.0 * d2 + cc1sq)),
                cc5,
                omgcof,
                xmcof,
                eta,
                delmo,
                sinmao,
            })
        };

        // secular angles as exact phases, in turns
        let mo = turns_of_degrees(&mo_deg);
        let argpo = turns_of_degrees(&argpo_deg);
        let sgp4 = Self {
            epoch: tle.epoch,
            radius_km: re,
            xke: g.xke.to_f32(),
            j2,
            ao_km,
            v_scale_kmps: (&(&radius_km * &g.xke) / 60.0).to_f32(),
            mean_anomaly: Phase::from_turns(&mo, &(&mdot * &INV_TAU)),
            arg_perigee: Phase::from_turns(&argpo, &(&argpdot * &INV_TAU)),
            node: Phase::from_turns(&turns_of_degrees(&nodeo_deg), &(&nodedot * &INV_TAU)),
            arg_latitude: Phase::from_turns(&(&mo + &argpo), &(&(&mdot + &argpdot) * &INV_TAU)),
            no: no32,
            ao,
            ecco,
            bstar,
            cosio,
            sinio,
            con41,
            x1mth2,
            x7thm1,
            cc1,
            cc4,
            nodecf,
            t2cof,
            xlcof,
            aycof,
            full_drag,
        };
        if !sgp4.coefficients_finite() {
            // e.g. η = 1 exactly (perigee at the drag reference height): a singular model
            return Err(Sgp4Error::Element {
                field: "eccentricity and perigee (singular drag coefficients)",
            });
        }
        sgp4.propagate_whole_frac(0, 0.0)?;
        Ok(sgp4)
    }

    /// Whether the stored coefficients are finite (field by field: no copy into an array).
    fn coefficients_finite(&self) -> bool {
        let common = finite32(self.no)
            && finite32(self.ao)
            && finite32(self.cc1)
            && finite32(self.cc4)
            && finite32(self.nodecf)
            && finite32(self.t2cof)
            && finite32(self.xlcof)
            && finite32(self.aycof);
        common
            && self.full_drag.as_ref().is_none_or(|d| {
                finite32(d.d2)
                    && finite32(d.d3)
                    && finite32(d.d4)
                    && finite32(d.t3cof)
                    && finite32(d.t4cof)
                    && finite32(d.t5cof)
                    && finite32(d.cc5)
                    && finite32(d.omgcof)
                    && finite32(d.xmcof)
                    && finite32(d.eta)
                    && finite32(d.delmo)
                    && finite32(d.sinmao)
            })
    }

    /// The epoch of the element set (UTC).
    pub fn epoch(&self) -> crate::time::Epoch<crate::time::Utc> {
        self.epoch
    }

    /// Position and velocity `since_epoch` after the element set's epoch (UTC days of 86 400 s,
    /// as SGP4 counts them).
    ///
    /// # Errors
    /// [`Sgp4Error::Eccentricity`], [`Sgp4Error::SemiLatusRectum`], [`Sgp4Error::Decayed`] as
    /// Vallado's `sgp4`; [`Sgp4Error::Diverged`] if the result is not finite.
    #[cfg_attr(target_arch = "msp430", inline(never))]
    pub fn propagate(&self, since_epoch: TimeSpan) -> Result<TemeState, Sgp4Error> {
        let (whole, frac) = split_span(since_epoch, 60);
        self.propagate_whole_frac(whole, frac)
    }

    /// As [`Sgp4::propagate`], for a time since epoch given as an f32 split pair
    /// `whole_min + frac_min` (such as [`TimeSpan::split_minutes`] returns; `whole_min` should be
    /// an integer for full precision, any fractional part is moved into `frac_min`).
    ///
    /// # Errors
    /// [`Sgp4Error::Time`] for a non-finite pair or |`whole_min`| > 10⁹; otherwise as
    /// [`Sgp4::propagate`].
    pub fn propagate_split(&self, whole_min: f32, frac_min: f32) -> Result<TemeState, Sgp4Error> {
        let t = whole_min + frac_min;
        if !t.is_finite() || fmath::abs(whole_min) > MAX_TSINCE_MIN {
            return Err(Sgp4Error::Time { tsince_min: t });
        }
        let w = fmath::floor(whole_min);
        let frac = (whole_min - w) + frac_min;
        let w2 = fmath::floor(frac);
        // |w| ≤ 1e9 and |frac| is finite but may be large: saturating conversions
        let whole = (w as i32).saturating_add(w2 as i32);
        self.propagate_whole_frac(whole, frac - w2)
    }

    /// The propagation proper (Vallado's `sgp4`, near-Earth), `t = whole + frac` minutes.
    fn propagate_whole_frac(&self, whole: i32, frac: f32) -> Result<TemeState, Sgp4Error> {
        let t = whole as f32 + frac;
        let t2 = t * t;

        // Secular gravity and drag: angles from their exact phases (−π..π)
        let xmdf = self.mean_anomaly.radians(whole, frac);
        let argpdf = self.arg_perigee.radians(whole, frac);
        let nodedf = self.node.radians(whole, frac);
        // Ω = Ω₀ + Ω̇t + nodecf·t²
        let nodem = nodedf + self.nodecf * t2;
        let mut tempa = 1.0 - self.cc1 * t;
        let mut tempe = self.bstar * self.cc4 * t;
        let mut templ = self.t2cof * t2;
        let mut argpm = argpdf;
        if let Some(d) = &self.full_drag {
            // δω = ω-cof·t; δM = M-cof·((1 + η cos M_df)³ − (1 + η cos M₀)³)
            let delomg = d.omgcof * t;
            // `sincos` rather than `cos` (bit-identical, see `fmath::sincos`): SGP4 was the only
            // caller of `cos` in the flight image: 954 B of code for ≈ 2 900 cycles
            let delm = d.xmcof * (cube32(1.0 + d.eta * fmath::sincos(xmdf).1) - d.delmo);
            let temp = delomg + delm;
            let mm = xmdf + temp;
            argpm = argpdf - temp;
            let t3 = t2 * t;
            let t4 = t3 * t;
            tempa = tempa - d.d2 * t2 - d.d3 * t3 - d.d4 * t4;
            tempe += self.bstar * d.cc5 * (fmath::sin(mm) - d.sinmao);
            templ += d.t3cof * t3 + t4 * (d.t4cof + t * d.t5cof);
        }
        // a = a₀″·tempa², n = kₑ/a^1.5 = n₀″/|tempa|³
        let am = self.ao * tempa * tempa;
        let nm = self.no / fmath::abs(tempa * tempa * tempa);
        let mut em = self.ecco - tempe;
        if !(em >= -0.001) || em >= 1.0 {
            return Err(Sgp4Error::Eccentricity {
                eccentricity: em,
                tsince_min: t,
            });
        }
        if !(em >= 1.0e-6) {
            em = 1.0e-6;
        }

        // Long-period periodics
        let (sin_argp, cos_argp) = fmath::sincos(argpm);
        let axnl = em * cos_argp;
        let temp = 1.0 / (am * (1.0 - em * em));
        let aynl = em * sin_argp + temp * self.aycof;
        // u = M + ω + n₀″·templ + xlcof-term, from the exact M + ω phase (δω and δM cancel)
        let u = self.arg_latitude.radians(whole, frac) + self.no * templ + temp * self.xlcof * axnl;

        // Kepler's equation for E + ω, Newton with steps clamped to ±0.95 rad
        let mut eo1 = u;
        let (mut sineo1, mut coseo1) = fmath::sincos(eo1);
        for _ in 0..KEPLER_MAX_ITERATIONS {
            let denom = 1.0 - coseo1 * axnl - sineo1 * aynl;
            let step = fmath::max(
                fmath::min((u - aynl * coseo1 + axnl * sineo1 - eo1) / denom, 0.95),
                -0.95,
            );
            eo1 += step;
            if !(fmath::abs(step) >= KEPLER_TOLERANCE) {
                // sin and cos of eo1 to first order in the (tiny) last step
                let s = sineo1 + coseo1 * step;
                coseo1 -= sineo1 * step;
                sineo1 = s;
                break;
            }
            (sineo1, coseo1) = fmath::sincos(eo1);
        }

        // Short-period preliminary quantities
        let ecose = axnl * coseo1 + aynl * sineo1;
        let esine = axnl * sineo1 - aynl * coseo1;
        let el2 = axnl * axnl + aynl * aynl;
        let pl = am * (1.0 - el2);
        if !(pl >= 0.0) {
            return Err(Sgp4Error::SemiLatusRectum { tsince_min: t });
        }
        let rl = am * (1.0 - ecose);
        let rdotl = fmath::sqrt(am) * esine / rl;
        let rvdotl = fmath::sqrt(pl) / rl;
        let betal = fmath::sqrt(1.0 - el2);
        let temp = esine / (1.0 + betal);
        let sinu = am / rl * (sineo1 - aynl - axnl * temp);
        let cosu = am / rl * (coseo1 - axnl + aynl * temp);
        let sin2u = (cosu + cosu) * sinu;
        let cos2u = 1.0 - 2.0 * sinu * sinu;
        let temp = 1.0 / pl;
        let temp1 = 0.5 * self.j2 * temp;
        let temp2 = temp1 * temp;

        // Short-period periodics
        // r_k = r_l(1 − 1.5·temp2·β_l·con41) + ½·temp1·x1mth2·cos 2u, in km with r_l = a(1 − e cos E)
        // and a = a₀″·tempa² scaled by the once-rounded a₀″ in km
        let r_km =
            self.ao_km * tempa * tempa * (1.0 - ecose) * (1.0 - 1.5 * temp2 * betal * self.con41)
                + 0.5 * temp1 * self.x1mth2 * cos2u * self.radius_km;
        // u_k = u − ¼·temp2·(7cos²i₀ − 1)·sin 2u, applied as a rotation of (sin u, cos u) (no
        // atan2, and u is never rounded to an f32 angle); (sinu, cosu) has unit norm to rounding,
        // restored by one Newton step of 1/√
        let dsu = -0.25 * temp2 * self.x7thm1 * sin2u;
        let norm = 1.5 - 0.5 * (sinu * sinu + cosu * cosu);
        let (sin_d, cos_d) = small_sincos(dsu);
        let sinsu = norm * (sinu * cos_d + cosu * sin_d);
        let cossu = norm * (cosu * cos_d - sinu * sin_d);
        let xnode = nodem + 1.5 * temp2 * self.cosio * sin2u;
        let xinc_delta = 1.5 * temp2 * self.cosio * self.sinio * cos2u;
        let mvt = rdotl - nm * temp1 * self.x1mth2 * sin2u / self.xke;
        let rvdot = rvdotl + nm * temp1 * (self.x1mth2 * cos2u + 1.5 * self.con41) / self.xke;

        // Orientation vectors
        let (snod, cnod) = fmath::sincos(xnode);
        // sin and cos of i = i₀ + δi from those of i₀ (δi is of order J₂)
        let (sdi, cdi) = small_sincos(xinc_delta);
        let sini = self.sinio * cdi + self.cosio * sdi;
        let cosi = self.cosio * cdi - self.sinio * sdi;
        let xmx = -snod * cosi;
        let xmy = cnod * cosi;
        let ux = xmx * sinsu + cnod * cossu;
        let uy = xmy * sinsu + snod * cossu;
        let uz = sini * sinsu;
        let vx = xmx * cossu - cnod * sinsu;
        let vy = xmy * cossu - snod * sinsu;
        let vz = sini * cossu;

        let v_scale = self.v_scale_kmps;
        let state = TemeState {
            r_teme_km: Vec3::new(ux, uy, uz) * r_km,
            v_teme_kmps: Vec3::new(
                mvt * ux + rvdot * vx,
                mvt * uy + rvdot * vy,
                mvt * uz + rvdot * vz,
            ) * v_scale,
        };
        if !(state.r_teme_km.iter().all(|x| x.is_finite())
            && state.v_teme_kmps.iter().all(|x| x.is_finite()))
        {
            return Err(Sgp4Error::Diverged { tsince_min: t });
        }
        // mrt < 1 (radius below one Earth radius)
        if !(r_km >= self.radius_km) {
            return Err(Sgp4Error::Decayed {
                tsince_min: t,
                radius_km: r_km,
            });
        }
        Ok(state)
    }
}

/// `(sin x, cos x)` of a small angle: a Taylor series to x³ for |x| < 0.01 rad (exact in f32,
/// the short-period corrections are of order J₂ ≈ 1e-3), `fmath::sincos` otherwise.
fn small_sincos(x: f32) -> (f32, f32) {
    if !(fmath::abs(x) >= 0.01) {
        let x2 = x * x;
        (x * (1.0 - x2 / 6.0), 1.0 - 0.5 * x2)
    } else {
        fmath::sincos(x)
    }
}

/// `x^(2/3)` for x > 0, as `cbrt(x)²` (double-f32).
fn two_thirds_power(x: &Df) -> Df {
    let c = x.cbrt();
    &c * &c
}

fn fourth_power(x: &Df) -> Df {
    let s = x * x;
    &s * &s
}

fn cube(x: f32) -> f32 {
    x * x * x
}

fn cube32(x: f32) -> f32 {
    x * x * x
}

/// Number of 32-bit words of an initialised element set ([`Sgp4::to_words`]).
pub const ELEMENT_WORDS: usize = 58;

/// Format tag of [`Sgp4::to_words`] (word 0): "S4", layout version 1.
const WORDS_TAG: u32 = 0x5334_0001;

/// Checksum of words `0..ELEMENT_WORDS − 1` of [`Sgp4::to_words`] (the last word): each word
/// rotated in by 5 bits, `c ← rotl(c, 5) ⊕ w` from `0x0acc5a7e` (a corrupted or truncated
/// uplink is refused; the link layer's CRC is the real protection). A change δ of word k
/// changes it by δ rotated left by 5·(56 − k), which lets the ground locate a single bad word.
pub fn words_checksum(words: &[u32]) -> u32 {
    words
        .iter()
        .fold(0x0acc_5a7e_u32, |c, w| c.rotate_left(5) ^ *w)
}

/// Reads the words in order, checking each; remembers the first bad index.
struct WordReader<'a> {
    words: core::slice::Iter<'a, u32>,
    index: u8,
    bad: Option<u8>,
}

impl WordReader<'_> {
    /// The next word (0 past the end, which marks it bad).
    fn word(&mut self) -> u32 {
        let w = self.words.next().copied();
        if w.is_none() {
            self.mark(self.index);
        }
        self.index = self.index.saturating_add(1);
        w.unwrap_or(0)
    }
    fn mark(&mut self, index: u8) {
        if self.bad.is_none() {
            self.bad = Some(index);
        }
    }
    /// The next word as a finite f32 (else marked bad).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn f32(&mut self) -> f32 {
        let index = self.index;
        let x = f32::from_bits(self.word());
        if !finite32(x) {
            self.mark(index);
        }
        x
    }
    fn i64(&mut self) -> i64 {
        let hi = self.word();
        let lo = self.word();
        ((u64::from(hi) << 32) | u64::from(lo)) as i64
    }
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn phase(&mut self) -> Phase {
        let at_epoch = self.i64();
        let rate_fx = self.i64();
        let rate_turns = self.f32();
        Phase::from_raw(at_epoch, rate_fx, rate_turns)
    }
}

/// Writes the words in order.
struct WordWriter<'a> {
    words: core::slice::IterMut<'a, u32>,
}

impl WordWriter<'_> {
    fn word(&mut self, w: u32) {
        if let Some(slot) = self.words.next() {
            *slot = w;
        }
    }
    fn f32(&mut self, x: f32) {
        self.word(x.to_bits());
    }
    fn i64(&mut self, x: i64) {
        self.word((x as u64 >> 32) as u32);
        self.word(x as u64 as u32);
    }
    fn phase(&mut self, p: &Phase) {
        let (at_epoch, rate_fx, rate_turns) = p.raw();
        self.i64(at_epoch);
        self.i64(rate_fx);
        self.f32(rate_turns);
    }
}

impl Sgp4 {
    /// The initialised element set as [`ELEMENT_WORDS`] 32-bit words, to be uplinked when the
    /// initialisation runs on the ground ([`Sgp4::from_words`] on board): a format tag, the
    /// epoch (day, second, nanosecond), the initialised constants and phases, the full-drag
    /// flag and terms (zero when absent), and a checksum.
    ///
    /// Initialisation on the host and on the MSP430 gives the same bits (checked by the
    /// firmware benchmark, `firmware/msp430-bench`), so the words do not depend on where they
    /// were made.
    pub fn to_words(&self) -> [u32; ELEMENT_WORDS] {
        let mut words = [0u32; ELEMENT_WORDS];
        let mut w = WordWriter {
            words: words.iter_mut(),
        };
        w.word(WORDS_TAG);
        w.word(self.epoch.day() as u32);
        w.word(self.epoch.second_of_day());
        w.word(self.epoch.nano());
        for x in [
            self.radius_km,
            self.xke,
            self.j2,
            self.ao_km,
            self.v_scale_kmps,
        ] {
            w.f32(x);
        }
        for p in [
            &self.mean_anomaly,
            &self.arg_perigee,
            &self.node,
            &self.arg_latitude,
        ] {
            w.phase(p);
        }
        for x in [
            self.no,
            self.ao,
            self.ecco,
            self.bstar,
            self.cosio,
            self.sinio,
            self.con41,
            self.x1mth2,
            self.x7thm1,
            self.cc1,
            self.cc4,
            self.nodecf,
            self.t2cof,
            self.xlcof,
            self.aycof,
        ] {
            w.f32(x);
        }
        w.word(u32::from(self.full_drag.is_some()));
        let d = self.full_drag.unwrap_or(FullDrag {
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
        });
        for x in [
            d.d2, d.d3, d.d4, d.t3cof, d.t4cof, d.t5cof, d.cc5, d.omgcof, d.xmcof, d.eta, d.delmo,
            d.sinmao,
        ] {
            w.f32(x);
        }
        let (body, last) = words.split_at_mut(ELEMENT_WORDS - 1);
        if let Some(sum) = last.first_mut() {
            *sum = words_checksum(body);
        }
        words
    }

    /// The element set [`Sgp4::to_words`] wrote, checked: the format tag, the checksum, the
    /// epoch, every constant finite, the phases in range and the drag flag 0 or 1, else
    /// [`Sgp4Error::Words`] with the first bad word. Propagation from it is bit for bit that of
    /// the element set that wrote it.
    #[cfg_attr(target_arch = "msp430", inline(never))]
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    pub fn from_words(words: &[u32; ELEMENT_WORDS]) -> Result<Self, Sgp4Error> {
        let (body, last) = words.split_at(ELEMENT_WORDS - 1);
        if last.first() != Some(&words_checksum(body)) {
            return Err(Sgp4Error::Words {
                index: (ELEMENT_WORDS - 1) as u8,
            });
        }
        let mut r = WordReader {
            words: body.iter(),
            index: 0,
            bad: None,
        };
        if r.word() != WORDS_TAG {
            return Err(Sgp4Error::Words { index: 0 });
        }
        let (day, second, nano) = (r.word() as i32, r.word(), r.word());
        let epoch = crate::time::Epoch::from_parts(day, second, nano)
            .map_err(|_| Sgp4Error::Words { index: 1 })?;
        // Each field read straight into the result, in the words' order (struct expressions
        // evaluate their fields as written): no intermediate copies (on the MSP430, 2 B of
        // code per word moved).
        let phase_index = r.index + 5;
        let mut orbit = Self {
            epoch,
            radius_km: r.f32(),
            xke: r.f32(),
            j2: r.f32(),
            ao_km: r.f32(),
            v_scale_kmps: r.f32(),
            mean_anomaly: r.phase(),
            arg_perigee: r.phase(),
            node: r.phase(),
            arg_latitude: r.phase(),
            no: r.f32(),
            ao: r.f32(),
            ecco: r.f32(),
            bstar: r.f32(),
            cosio: r.f32(),
            sinio: r.f32(),
            con41: r.f32(),
            x1mth2: r.f32(),
            x7thm1: r.f32(),
            cc1: r.f32(),
            cc4: r.f32(),
            nodecf: r.f32(),
            t2cof: r.f32(),
            xlcof: r.f32(),
            aycof: r.f32(),
            full_drag: None,
        };
        let flag_index = r.index;
        let flag = r.word();
        let drag = FullDrag {
            d2: r.f32(),
            d3: r.f32(),
            d4: r.f32(),
            t3cof: r.f32(),
            t4cof: r.f32(),
            t5cof: r.f32(),
            cc5: r.f32(),
            omgcof: r.f32(),
            xmcof: r.f32(),
            eta: r.f32(),
            delmo: r.f32(),
            sinmao: r.f32(),
        };
        if let Some(index) = r.bad {
            return Err(Sgp4Error::Words { index });
        }
        orbit.full_drag = match flag {
            0 => None,
            1 => Some(drag),
            _ => return Err(Sgp4Error::Words { index: flag_index }),
        };
        let phases_ok = [
            &orbit.mean_anomaly,
            &orbit.arg_perigee,
            &orbit.node,
            &orbit.arg_latitude,
        ]
        .iter()
        .all(|p| p.in_range());
        if !phases_ok {
            return Err(Sgp4Error::Words { index: phase_index });
        }
        Ok(orbit)
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
