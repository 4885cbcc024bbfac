//! Eclipse geometry: is the spacecraft in the Earth's shadow, and how much of the Sun does it see?
//!
//! Two models, both for a spacecraft position in TEME (km) and the geocentric Sun (any frame, the
//! same as the position's; in practice [`crate::env::sun::precise`]):
//!
//! - [`cylindrical`]: the shadow test of seed 003 §3.5 (note 003 §2.5, identical to PLAN13's):
//!   shadow iff the spacecraft is behind the Earth (`r·ŝ < 0`) and within one Earth radius of the
//!   Earth–Sun axis (`|r × ŝ| < R⊕`). No penumbra; in LEO its shadow edges are a few seconds off.
//! - [`conical`]: the umbra/penumbra model (O. Montenbruck, E. Gill, *Satellite Orbits*, 2000,
//!   §3.4.2, eqs. 3.85–3.87): the Sun and the Earth seen from the spacecraft are discs of angular
//!   radii `a = asin(R☉/|s − r|)` and `b = asin(R⊕/|r|)` whose centres are `c` apart; the visible
//!   fraction of the solar disc is one minus their overlap area over `π a²`.
//!
//! # Symbols
//! | name | symbol | meaning |
//! |---|---|---|
//! | `r_teme_km` | r | spacecraft position, geocentric (km) |
//! | `s_km` | s | geocentric Sun position (km) |
//! | `a` | a | apparent radius of the Sun seen from the spacecraft (rad) |
//! | `b` | b | apparent radius of the Earth seen from the spacecraft (rad) |
//! | `c` | c | angle between the centres of the two discs (rad) |
//! | `x`, `y` | x, y | chord geometry of the two overlapping circles (rad) |
//!
//! # Assumptions and accuracy
//! A spherical Earth of radius [`EARTH_RADIUS_KM`] (WGS-84 equatorial; the polar radius is
//! 21 km less, which moves a LEO shadow edge by up to about 3 s) without atmosphere (refraction
//! and absorption make the real penumbra a few seconds longer), the Sun a uniform disc (no limb
//! darkening) of radius [`SUN_RADIUS_KM`]. The f32 evaluation agrees with an f64 numerical
//! integration over the solar disc to the figure in `docs/accuracy.md` (`cargo test --test eclipse --
//! --nocapture`).
//!
//! Inputs that are not finite, a zero Sun vector or a position inside the Earth give an
//! [`EclipseError`].

use core::fmt;

use crate::env::sun::{Sun, AU_KM};
use crate::fmath;
use crate::linalg::{div, norm, Vec3};

/// Radius of the spherical Earth used by both models: WGS-84 equatorial radius (km).
pub const EARTH_RADIUS_KM: f32 = 6378.137;
/// Nominal solar radius (IAU 2015 resolution B3), km.
pub const SUN_RADIUS_KM: f32 = 695_700.0;

/// Errors of the eclipse models.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum EclipseError {
    /// A component of the spacecraft position is NaN or infinite.
    NonFinitePosition,
    /// A component of the Sun vector (or its distance) is NaN or infinite.
    NonFiniteSun,
    /// The Sun vector has zero length, or the Sun distance is not positive (carried: the length
    /// or distance).
    ZeroSun(f32),
    /// The spacecraft is inside the Earth (carried: its geocentric distance in km).
    InsideEarth(f32),
    /// The spacecraft is farther than [`MAX_RANGE_KM`] (carried: its distance in km, possibly
    /// infinite when the components are finite but their norm overflows).
    TooFar(f32),
}

/// The largest geocentric distance accepted (km): 1e9 km, about 6.7 au, far beyond any Earth
/// orbit and small enough that no product in the models overflows f32.
pub const MAX_RANGE_KM: f32 = 1.0e9;

impl fmt::Display for EclipseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NonFinitePosition => write!(f, "spacecraft position is not finite"),
            Self::NonFiniteSun => write!(f, "Sun vector is not finite"),
            Self::ZeroSun(l) => write!(f, "Sun vector length or distance {l} is not positive"),
            Self::InsideEarth(r) => write!(
                f,
                "spacecraft at {r} km from the geocentre is inside the Earth"
            ),
            Self::TooFar(r) => write!(f, "spacecraft at {r} km is beyond {MAX_RANGE_KM} km"),
        }
    }
}

/// Where the spacecraft is with respect to the Earth's shadow cone.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Shadow {
    /// The whole solar disc is visible.
    Sunlit,
    /// Part of the solar disc is hidden by the Earth.
    Penumbra,
    /// The Earth hides the whole solar disc.
    Umbra,
    /// Beyond the tip of the umbra (about 1.4 million km): the Earth is seen inside the solar disc.
    Antumbra,
}

/// The result of the conical model.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Illumination {
    /// Visible fraction of the solar disc, 0 (umbra) ..= 1 (sunlit).
    pub fraction: f32,
    /// The shadow region.
    pub shadow: Shadow,
}

/// All three components finite, tested from their bits (`f32::is_finite` over an iterator
/// was a loop of float comparisons on the MSP430).
fn finite3(v: &Vec3) -> bool {
    let finite = |x: f32| x.to_bits() & 0x7f80_0000 != 0x7f80_0000;
    finite(v.x) && finite(v.y) && finite(v.z)
}

fn check_position(r_teme_km: &Vec3) -> Result<f32, EclipseError> {
    if !finite3(r_teme_km) {
        return Err(EclipseError::NonFinitePosition);
    }
    let r = norm(r_teme_km);
    if !(r >= EARTH_RADIUS_KM) {
        return Err(EclipseError::InsideEarth(r));
    }
    if r > MAX_RANGE_KM {
        return Err(EclipseError::TooFar(r));
    }
    Ok(r)
}

fn check_direction(v: &Vec3) -> Result<Vec3, EclipseError> {
    if !finite3(v) {
        return Err(EclipseError::NonFiniteSun);
    }
    // Components are finite here. Scale by the largest first so that the norm cannot overflow or underflow.
    let largest = v.amax();
    if !(largest > 0.0) {
        return Err(EclipseError::ZeroSun(largest));
    }
    let scaled = div(v, largest);
    Ok(div(&scaled, norm(&scaled)))
}

/// The cylindrical shadow test of seed 003 (note 003 §2.5): `true` if the spacecraft is in
/// shadow, i.e. `r·ŝ < 0` and `|r × ŝ| < R⊕`.
///
/// `sun_direction` is the geocentric Sun direction (any length > 0, same frame as `r_teme_km`).
///
/// # Errors
/// [`EclipseError`] for non-finite input, a zero Sun vector or a position inside the Earth or
/// beyond [`MAX_RANGE_KM`].
pub fn cylindrical(r_teme_km: &Vec3, sun_direction: &Vec3) -> Result<bool, EclipseError> {
    Ok(!(cylindrical_margin_km(r_teme_km, sun_direction)? >= 0.0))
}

/// [`cylindrical`] as an [`Illumination`]: in shadow, fraction 0 and [`Shadow::Umbra`];
/// otherwise fraction 1 and [`Shadow::Sunlit`] (no penumbra: the cylinder's edge lies between
/// the conical model's umbra and penumbra edges, ≈ 4 s from each in low Earth orbit). The flight
/// loop's shadow test: it needs only to know when the Sun sensors cannot see the Sun, in ≈ 400 B
/// of MSP430 flash where [`conical`] takes ≈ 3 KB.
///
/// # Errors
/// As [`cylindrical`].
pub fn cylindrical_illumination(
    r_teme_km: &Vec3,
    sun_direction: &Vec3,
) -> Result<Illumination, EclipseError> {
    Ok(if cylindrical(r_teme_km, sun_direction)? {
        Illumination {
            fraction: 0.0,
            shadow: Shadow::Umbra,
        }
    } else {
        Illumination {
            fraction: 1.0,
            shadow: Shadow::Sunlit,
        }
    })
}

/// The signed distance (km) from the spacecraft to the surface of the shadow cylinder:
/// `|r × ŝ| − R⊕` behind the Earth (`r·ŝ < 0`), `|r| − R⊕` in front of it; negative in shadow,
/// continuous in time, zero at shadow entry and exit (for event search by bisection).
///
/// # Errors
/// As [`cylindrical`].
pub fn cylindrical_margin_km(r_teme_km: &Vec3, sun_direction: &Vec3) -> Result<f32, EclipseError> {
    let r = check_position(r_teme_km)?;
    let s_hat = check_direction(sun_direction)?;
    // Seed 003: Sw = acos(−r̂·ŝ) < 90° and SD = |r| sin Sw < R.
    let along = r_teme_km.dot(&s_hat);
    let off_axis_km = if !(along >= 0.0) {
        norm(&r_teme_km.cross(&s_hat))
    } else {
        r
    };
    Ok(off_axis_km - EARTH_RADIUS_KM)
}

/// The angles of the conical model (M&G eq. 3.85–3.86), all in radians, as seen from the
/// spacecraft.
///
/// Its margins are smooth functions of time whose zeros are the shadow boundaries, for event
/// search by bisection: [`ConeGeometry::penumbra_margin`] (negative inside the penumbra or the
/// umbra) and [`ConeGeometry::umbra_margin`] (negative inside the umbra).
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ConeGeometry {
    /// Apparent radius of the Sun, `a = asin(R☉/|s − r|)`.
    pub sun_radius_rad: f32,
    /// Apparent radius of the Earth, `b = asin(R⊕/|r|)`.
    pub earth_radius_rad: f32,
    /// Angle between the centres of the two discs, `c = ∠(−r, s − r)`.
    pub separation_rad: f32,
}

impl ConeGeometry {
    /// `c − (a + b)`: positive in full sun, zero at penumbra entry/exit.
    pub fn penumbra_margin(&self) -> f32 {
        self.separation_rad - (self.sun_radius_rad + self.earth_radius_rad)
    }

    /// `c − (b − a)`: negative in the umbra, zero at umbra entry/exit.
    pub fn umbra_margin(&self) -> f32 {
        self.separation_rad - (self.earth_radius_rad - self.sun_radius_rad)
    }
}

/// The apparent radii of the Sun and the Earth and their separation seen from the spacecraft.
///
/// `sun` is the geocentric Sun (direction and distance, same frame as `r_teme_km`).
///
/// # Errors
/// [`EclipseError`] for non-finite input, a zero Sun vector or distance, or a position inside
/// the Earth or beyond [`MAX_RANGE_KM`].
pub fn cone_geometry(r_teme_km: &Vec3, sun: &Sun) -> Result<ConeGeometry, EclipseError> {
    let r = check_position(r_teme_km)?;
    let s_hat = check_direction(&sun.direction)?;
    if !sun.distance_au.is_finite() {
        return Err(EclipseError::NonFiniteSun);
    }
    if !(sun.distance_au > 0.0) {
        return Err(EclipseError::ZeroSun(sun.distance_au));
    }
    let s_km = s_hat * (sun.distance_au * AU_KM);
    // Spacecraft → Sun and spacecraft → Earth centre.
    let to_sun = s_km - r_teme_km;
    let to_earth = -r_teme_km;
    let d_sun = norm(&to_sun);
    // a = asin(R☉/|s − r|), b = asin(R⊕/|r|)   (M&G eq. 3.85)
    let a = fmath::asin(fmath::min(SUN_RADIUS_KM / d_sun, 1.0));
    let b = fmath::asin(fmath::min(EARTH_RADIUS_KM / r, 1.0));
    // c = ∠(−r, s − r), from atan2 for accuracy near 0 and π.
    let c = fmath::atan2(norm(&to_earth.cross(&to_sun)), to_earth.dot(&to_sun));
    Ok(ConeGeometry {
        sun_radius_rad: a,
        earth_radius_rad: b,
        separation_rad: c,
    })
}

/// The conical umbra/penumbra model: the visible fraction of the solar disc and the region.
///
/// `sun` is the geocentric Sun (direction and distance, same frame as `r_teme_km`).
///
/// # Errors
/// As [`cone_geometry`].
#[cfg_attr(target_arch = "msp430", inline(never))]
pub fn conical(r_teme_km: &Vec3, sun: &Sun) -> Result<Illumination, EclipseError> {
    let g = cone_geometry(r_teme_km, sun)?;
    let (a, b, c) = (g.sun_radius_rad, g.earth_radius_rad, g.separation_rad);
    let sunlit = Illumination {
        fraction: 1.0,
        shadow: Shadow::Sunlit,
    };
    if c >= a + b {
        return Ok(sunlit);
    }
    if b - a >= c {
        return Ok(Illumination {
            fraction: 0.0,
            shadow: Shadow::Umbra,
        });
    }
    if a - b >= c {
        // The Earth's disc lies inside the Sun's: annular eclipse.
        return Ok(Illumination {
            fraction: 1.0 - (b * b) / (a * a),
            shadow: Shadow::Antumbra,
        });
    }
    // Partial overlap of two circles (M&G eq. 3.87), written as the sum of two circular
    // segments so that no term cancels in f32 (the Earth's segment is a sliver of a disc 250
    // times larger than the Sun's):
    // x = (c² + a² − b²)/(2c),  y = √(a² − x²)   (chord at distance x from the Sun's centre)
    // A = a²·acos(x/a) + b²·acos((c − x)/b) − c·y = seg(a, θa) + seg(b, θb),
    // θa = atan2(y, x), θb = atan2(y, c − x),  seg(ρ, θ) = ρ²(2θ − sin 2θ)/2
    let x = ((c - b) * (c + b) + a * a) / (2.0 * c);
    let y = fmath::sqrt(fmath::max((a - x) * (a + x), 0.0));
    let area = segment_area(a, fmath::atan2(y, x)) + segment_area(b, fmath::atan2(y, c - x));
    let fraction = fmath::min(
        fmath::max(1.0 - area / (core::f32::consts::PI * a * a), 0.0),
        1.0,
    );
    Ok(Illumination {
        fraction,
        shadow: Shadow::Penumbra,
    })
}

/// Area of the circular segment of a disc of radius `rho` cut by a chord that subtends the
/// half-angle `theta` at the centre: `ρ²(u − sin u)/2` with `u = 2θ`, by its Taylor series when
/// `u < 0.5` (relative error < 1e-9) to avoid the cancellation of `u − sin u`.
fn segment_area(rho: f32, theta: f32) -> f32 {
    let u = 2.0 * theta;
    let u_minus_sin_u = if !(u >= 0.5) {
        // u³/6 − u⁵/120 + u⁷/5040 − u⁹/362880
        let u2 = u * u;
        u * u2 * (1.0 / 6.0 - u2 * (1.0 / 120.0 - u2 * (1.0 / 5040.0 - u2 / 362_880.0)))
    } else {
        u - fmath::sin(u)
    };
    0.5 * rho * rho * u_minus_sin_u
}
