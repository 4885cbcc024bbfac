//! Sun direction and distance: Schlyter's model (the thesis's) and the project's precise model.
//!
//! | model | module | accuracy vs JPL DE421 (1990–2050, 400 instants) | cost |
//! |---|---|---|---|
//! | Schlyter's algorithm, seed 000 §7.1 | [`schlyter`] | 46.9″ max, 26.2″ RMS | 3 sincos, 1 atan2, 1 sqrt |
//! | VSOP87 (equation of the centre + 19 planetary/lunar terms) + 5-term nutation + aberration | [`precise`] | 2.22″ max, 0.82″ RMS (bound 15″) | 2 table sine-cosines, 36 table cosines, no f64; ≈ 47 400 MSP430 cycles |
//!
//! Both take an exact [`Epoch`](crate::time::Epoch) and never form a Julian date in f32: the whole
//! days and the fraction of the day are kept apart, and every angle that grows with time is
//! reduced modulo one turn in exact fixed-point arithmetic (`LinearAngle`) before it meets an
//! f32 product. The result is a [`Sun`]: a unit vector from the Earth's centre to the Sun and the
//! distance in astronomical units.
//!
//! Both are geocentric: seen from a spacecraft at `r` the Sun direction differs by up to
//! |r| / 1 au (4.7e-5 rad = 9.6″ at 7000 km); callers that need that subtract the position from
//! [`Sun::position_km`].

use core::fmt;

use crate::fmath;
use crate::linalg::Vec3;
use crate::time::{civil_from_days, TimeError, Wide};

pub mod precise;
pub mod schlyter;

/// The Sun as seen from the Earth's centre.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Sun {
    /// Unit vector from the geocentre towards the Sun (frame: see the model that produced it).
    pub direction: Vec3,
    /// Geocentric distance of the Sun in astronomical units (1 au = 149 597 870.7 km).
    pub distance_au: f32,
}

#[cfg(feature = "defmt")]
impl defmt::Format for Sun {
    fn format(&self, f: defmt::Formatter) {
        defmt::write!(
            f,
            "Sun {{ dir: [{}, {}, {}], {} au }}",
            self.direction.x,
            self.direction.y,
            self.direction.z,
            self.distance_au
        )
    }
}

/// One astronomical unit in km (IAU 2012 resolution B2).
pub const AU_KM: f32 = 149_597_870.7;

impl Sun {
    /// Right ascension (radians, −π..=π) and declination (radians) of [`Sun::direction`], in the
    /// frame of that vector.
    pub fn right_ascension_declination(&self) -> (f32, f32) {
        let d = &self.direction;
        let ra = fmath::atan2(d.y, d.x);
        let dec = fmath::atan2(d.z, fmath::sqrt(d.x * d.x + d.y * d.y));
        (ra, dec)
    }

    /// The geocentric Sun vector in km (direction × distance).
    pub fn position_km(&self) -> Vec3 {
        self.direction * (self.distance_au * AU_KM)
    }
}

/// Errors of the Sun models.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum SunError {
    /// The instant's year lies outside the model's range of validity (carried: the year).
    Year(i32),
    /// The time conversion (UTC → TT) failed.
    Time(TimeError),
}

impl fmt::Display for SunError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Year(y) => write!(f, "year {y} outside the Sun model's range"),
            Self::Time(e) => write!(f, "time conversion failed: {e}"),
        }
    }
}

impl From<TimeError> for SunError {
    fn from(e: TimeError) -> Self {
        Self::Time(e)
    }
}

/// The Gregorian year of a day count from 2000-01-01, for the range errors (exact for every day
/// count: [`civil_from_days`]).
pub(crate) fn year_of_day(day: i32) -> i32 {
    civil_from_days(day).0
}

/// 2^48 as f64: the fixed-point scale of [`LinearAngle`] (one turn = 2^48 units).
const TURN_Q48: f64 = 281_474_976_710_656.0;

/// An angle that grows linearly with time, `θ(n + f) = θ₀ + ω·(n + f)`, with `n` whole days and
/// `f` a fraction of a day, evaluated without losing bits to the size of `ω·n`.
///
/// `θ₀ + ω·n` is formed in 64-bit fixed point with 2^48 units per turn, where wrapping arithmetic
/// keeps the fraction of a turn exact whatever `n`; only the fraction (|x| ≤ ½ turn) reaches
/// f32, so the result carries the f32 rounding of a number below π (≤ 2.4e-7 rad = 0.05″) and the
/// 2^-48 turn/day quantisation of `ω` (1.6e-10″ per day), not the 1e-3 rad that an f32 product
/// `ω·n` would lose after 50 years. The 64-bit words are [`Wide`] (16-bit products: no 64-bit
/// library call on the MSP430).
#[derive(Copy, Clone, Debug, PartialEq)]
pub(crate) struct LinearAngle {
    /// θ₀ in 2^-48 turn.
    at_zero_q48: Wide,
    /// ω in 2^-48 turn per day (two's complement).
    rate_q48: Wide,
    /// ω in turns per day, for the fraction of the day.
    rate_turns_per_day: f32,
}

impl LinearAngle {
    /// From θ₀ in degrees and ω in degrees per day.
    pub(crate) const fn from_degrees(at_zero_deg: f64, rate_deg_per_day: f64) -> Self {
        Self::from_turns(at_zero_deg / 360.0, rate_deg_per_day / 360.0)
    }

    /// From θ₀ in radians and ω in radians per Julian millennium (365 250 days), VSOP87's units.
    pub(crate) const fn from_radians_per_millennium(at_zero_rad: f64, rate_rad: f64) -> Self {
        let turn = 2.0 * core::f64::consts::PI;
        Self::from_turns(at_zero_rad / turn, rate_rad / turn / 365_250.0)
    }

    const fn from_turns(at_zero: f64, rate_per_day: f64) -> Self {
        // Reduce θ₀ to one turn first so that the conversion to i64 cannot saturate.
        let whole = at_zero as i64;
        Self {
            at_zero_q48: Wide::from_u64(((at_zero - whole as f64) * TURN_Q48) as i64 as u64),
            rate_q48: Wide::from_u64((rate_per_day * TURN_Q48) as i64 as u64),
            rate_turns_per_day: rate_per_day as f32,
        }
    }

    /// The angle in radians, reduced to about −π..π (exactly −π..π plus |ω·f|), at `n` whole days
    /// plus `f` days (|f| ≤ 1) after the angle's day zero.
    pub(crate) fn radians(&self, n: i32, f: f32) -> f32 {
        self.turns(n, f) * core::f32::consts::TAU
    }

    /// As [`LinearAngle::radians`], in turns (about −½..½).
    pub(crate) fn turns(&self, n: i32, f: f32) -> f32 {
        let q = self
            .at_zero_q48
            .wrapping_add(self.rate_q48.wrapping_mul_i32(n));
        // The low 48 bits are a signed fraction of a turn in [−½, ½): its bits 16..=47 as an i32
        // (the sign bit 47 on top), then its top 24 bits rounded (half up), which an f32 holds
        // exactly: ⌊(x + 2^7)/2^8⌋ without the overflow of x + 2^7.
        let x = ((q.hi() << 16) | (q.lo() >> 16)) as i32;
        let frac_q24 = (x >> 8) + ((x >> 7) & 1);
        frac_q24 as f32 * (1.0 / 16_777_216.0) + self.rate_turns_per_day * f
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 32-bit words give the bits of the former `i64` formula.
    #[test]
    fn linear_angle_in_words_equals_i64() {
        let a = LinearAngle::from_radians_per_millennium(
            1.753_470_46 + core::f64::consts::PI,
            6_283.319_667_47,
        );
        let b = LinearAngle::from_degrees(356.0470, -0.9856002585);
        for angle in [a, b] {
            let (at_zero, rate) = (
                angle.at_zero_q48.to_u64() as i64,
                angle.rate_q48.to_u64() as i64,
            );
            for n in (-2_000_000..2_000_000)
                .step_by(37)
                .chain([i32::MIN, i32::MAX])
            {
                let q = at_zero.wrapping_add(rate.wrapping_mul(i64::from(n)));
                let frac_q48 = q.wrapping_shl(16).wrapping_shr(16);
                let frac_q24 = ((frac_q48 + (1 << 23)) >> 24) as i32;
                let expected =
                    frac_q24 as f32 * (1.0 / 16_777_216.0) + angle.rate_turns_per_day * 0.3;
                assert_eq!(angle.turns(n, 0.3).to_bits(), expected.to_bits(), "{n}");
            }
        }
    }

    #[test]
    fn linear_angle_matches_f64_over_a_century() {
        // Sun's mean anomaly (Schlyter): 356.0470° + 0.9856002585°/day.
        let a = LinearAngle::from_degrees(356.0470, 0.9856002585);
        for &(n, f) in &[
            (0, 0.0f32),
            (1, 0.25),
            (18_262, -0.4),
            (-36_525, 0.49),
            (36_525, 0.0),
        ] {
            let exact = (356.0470 + 0.9856002585 * (f64::from(n) + f64::from(f))).to_radians();
            let got = f64::from(a.radians(n, f));
            let diff = (got - exact).rem_euclid(core::f64::consts::TAU);
            let diff = diff.min(core::f64::consts::TAU - diff);
            assert!(diff < 4e-7, "n={n} f={f}: diff {diff} rad");
        }
    }
}
