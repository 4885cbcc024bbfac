//! Time: split-precision epochs, time scales, calendar and Julian dates, TLE epochs, GMST.
//!
//! # Why split precision
//! A Julian date near 2.45e6 in f32 has a resolution of 0.25 day: seed 000 lost 63 minutes that
//! way (note 000 §0.3). An [`Epoch`] here is an integer day count, an integer second of the day
//! and integer nanoseconds, so it is exact; a [`TimeSpan`] between two epochs is integer seconds
//! and nanoseconds, and models take it as a split pair of f32 values ([`TimeSpan::split_minutes`])
//! so that no bits are lost before the model reduces its angles.
//!
//! # Time scales
//! The scale is a type parameter ([`Utc`], [`Tai`], [`Tt`], [`Ut1`]), so an epoch of one scale
//! cannot be subtracted from another by mistake. UTC days have 86 400 s except at a leap second,
//! which the UTC epoch represents as second 86 400 of the day (see [`LEAP_SECONDS`]). Within UTC,
//! [`Epoch::span_since`] counts days as 86 400 s (as SGP4 and Vallado's `jday` do); convert to TAI
//! or TT first for a span that includes leap seconds.
//!
//! # Symbols
//! | name | meaning |
//! |---|---|
//! | `day` | whole days since 2000-01-01 00:00 of the epoch's scale (MJD − 51 544) |
//! | `second` | whole seconds of the day, 0..=86 400 |
//! | `nano` | nanoseconds of the second, 0..1e9 |
//! | `jd` | Julian date, days since −4712-01-01 12:00 |
//! | `d` | seed 000's day number (eq. 7.1), days since 1999-12-31 00:00 (= JD − 2 451 543.5) |
//! | `T` | Julian centuries of UT1 since J2000.0 (Vallado 2013 eq. 3-42) |
//! | `θ_GMST` | Greenwich mean sidereal time (IAU-82), Vallado 2013 eq. 3-45 |
//!
//! # Scale conversions
//! - UTC → TAI: `TAI = UTC + ΔAT` with ΔAT from [`LEAP_SECONDS`] (IERS Bulletin C), integer
//!   seconds since 1972-01-01; [`Epoch::<Utc>::to_tai`] refuses epochs before 1972 and after
//!   [`LEAP_SECONDS_VALID_UNTIL`] (use [`Epoch::<Utc>::to_tai_extrapolated`] to accept the last
//!   offset after it); [`Epoch::<Tai>::to_utc`] is the exact inverse, leap second included.
//! - TAI → TT: `TT = TAI + 32.184 s` (exact).
//! - UTC → UT1: `UT1 = UTC + DUT1`, |DUT1| ≤ 0.9 s by definition of UTC; [`Epoch::<Utc>::to_ut1`]
//!   takes DUT1 from IERS Bulletin A if the caller has it, else relabels (UT1 ≈ UTC: GMST then off
//!   by up to 0.9 s × 7.29e-5 rad/s = 6.6e-5 rad, 0.46 km along the equator at LEO radius).
//!
//! # Arithmetic
//! Everything a flight computer calls is i32/u32 arithmetic (each function states why its values
//! fit): on the MSP430 a 64-bit division is a library call of about 3.4 KB of code and thousands of
//! cycles, a 64-bit product about 900 cycles. GMST's 64-bit binary angle is two 32-bit words
//! formed from 16 × 16-bit products. UTC → TT costs 792 MSP430 cycles, GMST 8 650
//! (`docs/firmware.md`, "MSP430 firmware and cycle budget"). The f64 functions are for host code.
//!
//! # Accuracy (measured, `cargo test --test time -- --nocapture`)
//! - [`gmst_rad`] (f32) against Vallado's `gstime` in f64 over 1990–2050: max error
//!   2.40e-7 rad, RMS 9.2e-8 rad (one f32 rounding of the result; 1.7 m at 7000 km);
//!   [`gmst_rad_f64`]: max 4.9e-11 rad, the f64 reference's own rounding.

use core::fmt;
use core::marker::PhantomData;

/// Seconds in a day of 86 400 SI seconds.
pub const SECONDS_PER_DAY: u32 = 86_400;
/// Nanoseconds in a second.
pub const NANOS_PER_SECOND: u32 = 1_000_000_000;
/// Julian date of 2000-01-01 00:00 (day 0 of [`Epoch`]).
pub const JD_DAY0: f64 = 2_451_544.5;
/// Modified Julian date of 2000-01-01 00:00.
pub const MJD_DAY0: i32 = 51_544;

/// A time scale, as a type-level tag.
pub trait TimeScale: Copy + Clone + fmt::Debug + PartialEq + Eq + Default {
    /// Short name ("UTC", "TAI", "TT", "UT1").
    const NAME: &'static str;
}

macro_rules! time_scale {
    ($name:ident, $text:literal, $doc:literal) => {
        #[doc = $doc]
        #[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
        pub struct $name;
        impl TimeScale for $name {
            const NAME: &'static str = $text;
        }
    };
}
time_scale!(
    Utc,
    "UTC",
    "Coordinated Universal Time (with leap seconds)."
);
time_scale!(Tai, "TAI", "International Atomic Time.");
time_scale!(Tt, "TT", "Terrestrial Time, TAI + 32.184 s.");
time_scale!(Ut1, "UT1", "Universal Time UT1 (Earth rotation angle).");

/// Errors of the time functions.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum TimeError {
    /// Month outside 1..=12.
    Month(u8),
    /// Day outside the month.
    Day(u8),
    /// Hour, minute or second outside its range.
    TimeOfDay,
    /// Nanoseconds ≥ 1e9.
    Nanos(u32),
    /// Year outside the supported range 1900..=2100.
    Year(i32),
    /// Day of year outside 1..=366 (TLE epoch).
    DayOfYear(u16),
    /// A non-finite or out-of-range number of seconds or days.
    OutOfRange,
    /// A UTC (or TAI) epoch before 1972-01-01, when UTC had no integer TAI − UTC offset; carries
    /// the year. See [`LEAP_SECONDS`].
    BeforeLeapSeconds(i32),
    /// A UTC (or TAI) epoch after [`LEAP_SECONDS_VALID_UNTIL`], where a leap second may have been
    /// announced since the table was written; carries the year. Use the `_extrapolated`
    /// conversions to accept the last offset.
    AfterLeapSeconds(i32),
    /// Second 60 (second 86 400 of the day) on a UTC day that had no leap second; carries the
    /// days since 2000-01-01.
    NotALeapSecond(i32),
    /// |UT1 − UTC| above 0.9 s; carries the offending value in milliseconds.
    Dut1(i32),
}

impl fmt::Display for TimeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Month(m) => write!(f, "month {m} outside 1..=12"),
            Self::Day(d) => write!(f, "day {d} outside the month"),
            Self::TimeOfDay => write!(f, "hour, minute or second out of range"),
            Self::Nanos(n) => write!(f, "nanoseconds {n} not below 1e9"),
            Self::Year(y) => write!(f, "year {y} outside 1900..=2100"),
            Self::DayOfYear(d) => write!(f, "day of year {d} outside 1..=366"),
            Self::OutOfRange => write!(f, "time value not finite or out of range"),
            Self::BeforeLeapSeconds(y) => {
                write!(f, "year {y}: UTC before 1972 has no leap-second offset")
            }
            Self::AfterLeapSeconds(y) => write!(
                f,
                "year {y}: after the leap-second table's end (LEAP_SECONDS_VALID_UNTIL)"
            ),
            Self::NotALeapSecond(d) => {
                write!(
                    f,
                    "second 60 on day {d} since 2000-01-01, which had no leap second"
                )
            }
            Self::Dut1(ms) => write!(f, "UT1 - UTC = {ms} ms outside +-900 ms"),
        }
    }
}

/// An instant in time scale `S`, exact to the nanosecond.
///
/// Ordered by (day, second, nano). Construct it from a calendar date
/// ([`Epoch::from_calendar`]), a TLE epoch ([`Epoch::from_tle_epoch`]) or a day count.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Epoch<S: TimeScale> {
    day: i32,
    second: u32,
    nano: u32,
    scale: PhantomData<S>,
}

#[cfg(feature = "defmt")]
impl<S: TimeScale> defmt::Format for Epoch<S> {
    fn format(&self, f: defmt::Formatter) {
        defmt::write!(
            f,
            "{}+{}s+{}ns {}",
            self.day,
            self.second,
            self.nano,
            S::NAME
        )
    }
}

/// A signed duration: whole seconds plus nanoseconds in `0..1e9` (so −0.25 s is −1 s + 0.75e9 ns).
///
/// The range (±68 years) covers every propagation span this crate accepts.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TimeSpan {
    seconds: i32,
    nano: u32,
}

/// A calendar date and time of day, as read by people (in the epoch's own scale).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Calendar {
    /// Year (Gregorian).
    pub year: i32,
    /// Month 1..=12.
    pub month: u8,
    /// Day of the month 1..=31.
    pub day: u8,
    /// Hour 0..=23.
    pub hour: u8,
    /// Minute 0..=59.
    pub minute: u8,
    /// Second 0..=60 (60 only during a UTC leap second).
    pub second: u8,
    /// Nanoseconds 0..1e9.
    pub nano: u32,
}

/// Days from 2000-01-01 to the given Gregorian date (proleptic), exact integer arithmetic.
///
/// The algorithm is the "days from civil" of H. Hinnant (public domain), shifted to 2000-01-01.
///
/// Computed in `i32` (no 64-bit division or multiply: on the MSP430 those are library calls of
/// about 3.4 KB and 1 000 cycles each); the result saturates at the ends of `i32` (years beyond
/// ±5.8 million). Range argument: the 400-year era is at most 5.4e6 in magnitude, the day of the
/// era at most 1.6e5 (any `month` and `day` byte), and the era's days, `era·146 097`, are only
/// formed for the 14 700 eras that fit `i32` (beyond them the result is saturated anyway).
pub const fn days_from_civil(year: i32, month: u8, day: u8) -> i32 {
    // The year y = year − 1 for January and February (without forming it: no overflow at
    // i32::MIN), split into its era (floor division by 400) and its year of the era.
    let mut era = year.div_euclid(400);
    let mut yoe = year.rem_euclid(400);
    if 2 >= month {
        if yoe == 0 {
            yoe = 399;
            era -= 1;
        } else {
            yoe -= 1;
        }
    }
    let m = month as i32;
    let mp = if m > 2 { m - 3 } else { m + 9 };
    let doy = (153 * mp + 2) / 5 + day as i32 - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    // days = era·146 097 + doe − 730 425, saturated: −1 ≤ doe ≤ 153 696; a non-negative era is
    // written (era − 5)·146 097 + (doe + 60) so that the second term is positive, a negative one
    // keeps its negative second term, so an era whose product leaves i32 saturates the sum too.
    if era >= 0 {
        if era > 14_704 {
            i32::MAX
        } else {
            ((era - 5) * 146_097).saturating_add(doe + 60)
        }
    } else if -14_699 > era {
        i32::MIN
    } else {
        (era * 146_097).saturating_add(doe - 730_425)
    }
}

/// The Gregorian (year, month, day) of a day count from 2000-01-01 (inverse of [`days_from_civil`]).
///
/// Exact for every `i32` day count (see `march_year`).
pub const fn civil_from_days(days: i32) -> (i32, u8, u8) {
    let (y, doy, _) = march_year(days);
    // 0 ≤ mp ≤ 11 (u16 arithmetic is a few instructions on the MSP430, i32 a library call)
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if 10 > mp { mp + 3 } else { mp - 9 };
    let year = if 2 >= m { y + 1 } else { y };
    (year, m as u8, d as u8)
}

/// The March-based year of a day count from 2000-01-01 (the Gregorian year of its 1 March), the
/// day's index in it (0 ≤ doy ≤ 365, 0 on 1 March, the leap day last) and the year of its
/// 400-year era (0 ≤ yoe ≤ 399): the common part of [`civil_from_days`] and
/// [`year_from_days`].
///
/// Exact for every `i32` day count, in `i32` arithmetic: the era (|era| ≤ 14 705) and the day of
/// the era (0..=146 096) come from one division of the day count itself (the usual shift to
/// 0000-03-01, 730 425 days, would overflow near `i32::MAX`), the rest is small.
#[inline(always)]
const fn march_year(days: i32) -> (i32, u16, u16) {
    // days + 730 425 = (q + 5)·146 097 + (r − 60), with 0 ≤ r < 146 097
    let q = days.div_euclid(146_097);
    let r = days.rem_euclid(146_097);
    let (era, doe) = if r >= 60 {
        (q + 5, r - 60)
    } else {
        (q + 4, r + 146_037)
    };
    // From here on everything is non-negative; below the year of the era it fits 16 bits.
    let doe = doe as u32;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let y = yoe as i32 + era * 400;
    let doy = (doe - (365 * yoe + yoe / 4 - yoe / 100)) as u16;
    (y, doy, yoe as u16)
}

/// The Gregorian year of a day count from 2000-01-01, the day's index in it (0 on 1 January, as
/// `days − days_from_civil(year, 1, 1)`) and whether the year is a leap year
/// ([`is_leap_year`]): the year of [`civil_from_days`], without its month and day.
///
/// The same March-based year of the 400-year era as [`civil_from_days`] (`march_year`), then:
/// its days 306 and on are January and February of the next Gregorian year, days 0..306 are
/// March to December, after the 59 or 60 days of January and February. The year's leap test is made on the year of the era (0..400, whose 0 is the era's own multiple of
/// 400), in 16-bit arithmetic; no division of the year itself.
pub const fn year_from_days(days: i32) -> (i32, u16, bool) {
    let (y, doy, yoe) = march_year(days);
    if doy >= 306 {
        // January or February of year y + 1 (y + 1 ≡ yoe + 1 modulo 400, 1 ≤ yoe + 1 ≤ 400)
        let next = yoe + 1;
        let leap = next.is_multiple_of(4) && (!next.is_multiple_of(100) || next == 400);
        (y + 1, doy - 306, leap)
    } else {
        // March to December of year y (y ≡ yoe modulo 400)
        let leap = yoe.is_multiple_of(4) && (!yoe.is_multiple_of(100) || yoe == 0);
        (y, doy + if leap { 60 } else { 59 }, leap)
    }
}

/// True for a Gregorian leap year.
pub const fn is_leap_year(year: i32) -> bool {
    (year % 4 == 0 && year % 100 != 0) || year % 400 == 0
}

/// Number of days in a month of a year.
pub const fn days_in_month(year: i32, month: u8) -> u8 {
    match month {
        1 | 3 | 5 | 7 | 8 | 10 | 12 => 31,
        4 | 6 | 9 | 11 => 30,
        2 if is_leap_year(year) => 29,
        2 => 28,
        _ => 0,
    }
}

impl<S: TimeScale> Epoch<S> {
    /// Smallest supported year.
    pub const MIN_YEAR: i32 = 1900;
    /// Largest supported year.
    pub const MAX_YEAR: i32 = 2100;

    /// 2000-01-01 00:00 of the scale (day 0): a placeholder date, e.g. in a message whose clock
    /// is not valid.
    pub const DAY0: Self = Self {
        day: 0,
        second: 0,
        nano: 0,
        scale: PhantomData,
    };

    /// An epoch from its parts: days since 2000-01-01, second of day (0..=86 400), nanoseconds.
    pub const fn from_parts(day: i32, second: u32, nano: u32) -> Result<Self, TimeError> {
        if second > SECONDS_PER_DAY {
            return Err(TimeError::TimeOfDay);
        }
        if nano >= NANOS_PER_SECOND {
            return Err(TimeError::Nanos(nano));
        }
        Ok(Self {
            day,
            second,
            nano,
            scale: PhantomData,
        })
    }

    /// An epoch from a Gregorian calendar date and time of day in scale `S`.
    ///
    /// Second 60 is accepted (a UTC leap second; the caller is responsible for its validity).
    pub fn from_calendar(c: Calendar) -> Result<Self, TimeError> {
        if !(c.year >= Self::MIN_YEAR && Self::MAX_YEAR >= c.year) {
            return Err(TimeError::Year(c.year));
        }
        if !(c.month >= 1 && 12 >= c.month) {
            return Err(TimeError::Month(c.month));
        }
        if c.day == 0 || c.day > days_in_month(c.year, c.month) {
            return Err(TimeError::Day(c.day));
        }
        if c.hour > 23 || c.minute > 59 || c.second > 60 {
            return Err(TimeError::TimeOfDay);
        }
        let second = u32::from(c.hour) * 3600 + u32::from(c.minute) * 60 + u32::from(c.second);
        Self::from_parts(days_from_civil(c.year, c.month, c.day), second, c.nano)
    }

    /// The calendar date and time of day of this epoch (in scale `S`).
    pub fn to_calendar(&self) -> Calendar {
        let (year, month, day) = civil_from_days(self.day);
        // second 86 400 is a leap second: 23:59:60
        let (hour, minute, second) = if self.second >= SECONDS_PER_DAY {
            (23, 59, 60)
        } else {
            let s = self.second;
            ((s / 3600) as u8, ((s % 3600) / 60) as u8, (s % 60) as u8)
        };
        Calendar {
            year,
            month,
            day,
            hour,
            minute,
            second,
            nano: self.nano,
        }
    }

    /// Whole days since 2000-01-01 00:00 of this scale.
    pub const fn day(&self) -> i32 {
        self.day
    }

    /// Whole seconds of the day (0..=86 400).
    pub const fn second_of_day(&self) -> u32 {
        self.second
    }

    /// Nanoseconds of the second.
    pub const fn nano(&self) -> u32 {
        self.nano
    }

    /// The fraction of the day elapsed, in f32 (resolution 6e-8 day = 5 ms near the day's end:
    /// fine for slowly varying models such as the Sun; use [`Epoch::span_since`] for orbits).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    pub fn day_fraction_f32(&self) -> f32 {
        (self.second as f32 + self.nano as f32 * 1e-9) / SECONDS_PER_DAY as f32
    }

    /// The Julian date as two f64 parts `(jd_whole, fraction)`: `jd_whole` ends in .5 (midnight)
    /// and `fraction` is in 0..=1. Their sum is the Julian date; keep them apart for precision.
    pub fn jd_split(&self) -> (f64, f64) {
        let whole = JD_DAY0 + self.day as f64;
        let frac = (self.second as f64 + self.nano as f64 * 1e-9) / SECONDS_PER_DAY as f64;
        (whole, frac)
    }

    /// Days since 2000-01-01 12:00 (J2000.0 of this scale) as an exact pair
    /// `(whole_days, fraction)`, both f32, `fraction` in −0.5..=0.5.
    ///
    /// `whole_days` is an integer (exact in f32 for the ±16 million days of interest).
    pub fn days_since_j2000_split(&self) -> (f32, f32) {
        let frac = self.day_fraction_f32() - 0.5;
        (self.day as f32, frac)
    }

    /// Julian centuries since J2000.0 (2000-01-01 12:00 of this scale), f64:
    /// `T = (JD − 2 451 545.0) / 36 525` (Vallado 2013 eq. 3-42), from the exact split.
    pub fn julian_centuries_since_j2000_f64(&self) -> f64 {
        let seconds = f64::from(self.second) - 43_200.0 + f64::from(self.nano) * 1e-9;
        (f64::from(self.day) + seconds / f64::from(SECONDS_PER_DAY)) / 36_525.0
    }

    /// Julian centuries since J2000.0 of this scale in f32 (resolution 3e-9 century = 9 s at
    /// 2050; for slowly varying terms such as nutation and precession arguments).
    pub fn julian_centuries_since_j2000_f32(&self) -> f32 {
        let (whole, fraction) = self.days_since_j2000_split();
        (whole + fraction) / 36_525.0
    }

    /// Seconds from `earlier` to `self` in f32, whole and fractional parts added (exact enough
    /// for a control period or a slew's progress: 1 ms at 4.6 hours).
    pub fn seconds_since_f32(&self, earlier: &Self) -> f32 {
        let (whole, frac) = self.span_since(earlier).split_seconds();
        whole + frac
    }

    /// [`Epoch::seconds_since_f32`], the same value in fewer bytes of MSP430 code (the attitude
    /// node's clock check): the span's whole seconds as `clamp(d·86 400 + Δs)` with one
    /// saturating addition (`(t + Δs) + t`, `t = d·43 200`) instead of [`Epoch::span_since`]'s
    /// sign-split terms; the same ends.
    pub(crate) fn seconds_since_f32_small(&self, earlier: &Self) -> f32 {
        // as `span_since`'s borrow: (self.nano + 1e9) − earlier.nano when it is smaller
        let mut nano = self.nano.wrapping_sub(earlier.nano);
        let mut borrow = 0;
        if earlier.nano > self.nano {
            nano = nano.wrapping_add(NANOS_PER_SECOND);
            borrow = 1;
        }
        // −86 401 ≤ ds ≤ 86 400
        let ds = self.second as i32 - earlier.second as i32 - borrow;
        let later = self.day >= earlier.day;
        let d = self.day.wrapping_sub(earlier.day);
        // a wrapped difference, or one beyond ±24 856 days: saturated, as `span_since`
        let seconds = if later != (d >= 0) || d > 24_856 || -24_856 > d {
            if later {
                i32::MAX
            } else {
                i32::MIN
            }
        } else {
            // |t| ≤ 1 073 779 200 and |t + ds| fit i32: one saturating addition, exact
            let t = d * (SECONDS_PER_DAY / 2) as i32;
            (t + ds).saturating_add(t)
        };
        seconds as f32 + nano as f32 * 1e-9
    }

    /// The span from `earlier` to `self` (negative if `earlier` is later). UTC days count 86 400 s.
    /// Saturates at the ends of [`TimeSpan`] (±68 years).
    pub fn span_since(&self, earlier: &Self) -> TimeSpan {
        // i32 arithmetic only (64-bit products and divisions are library calls on the MSP430).
        let (nano, borrow) = match self.nano.checked_sub(earlier.nano) {
            Some(n) => (n, 0),
            None => ((self.nano + NANOS_PER_SECOND) - earlier.nano, 1),
        };
        // −86 401 ≤ ds ≤ 86 400
        let ds = self.second as i32 - earlier.second as i32 - borrow;
        let later = self.day >= earlier.day;
        let d = self.day.wrapping_sub(earlier.day);
        // Beyond ±24 856 days the span is beyond ±(24 857·86 400 − 86 401) s > i32::MAX: saturated.
        // Within, d·86 400 + ds = (d − sgn d)·86 400 + (ds + 86 400·sgn d), both terms in i32.
        let seconds = if later && (0 > d || d > 24_856) {
            i32::MAX
        } else if !later && (-24_856 > d || d >= 0) {
            i32::MIN
        } else {
            let sgn = if d > 0 {
                1
            } else if 0 > d {
                -1
            } else {
                0
            };
            ((d - sgn) * SECONDS_PER_DAY as i32).saturating_add(ds + sgn * SECONDS_PER_DAY as i32)
        };
        TimeSpan { seconds, nano }
    }

    /// This epoch moved by `span` (days count 86 400 s). Saturates at the ends of the day range.
    pub fn add(&self, span: TimeSpan) -> Self {
        // nano < 2e9 and second < 2·86 400 + 1 fit u32; no 64-bit arithmetic.
        let (nano, carry) = match (self.nano + span.nano).checked_sub(NANOS_PER_SECOND) {
            Some(n) => (n, 1),
            None => (self.nano + span.nano, 0),
        };
        // Whole days and seconds of the span; spans under a day (leap-second and time-scale
        // offsets, control periods) skip the division.
        let spd = SECONDS_PER_DAY as i32;
        let (days, rem) = if span.seconds >= 0 && spd > span.seconds {
            (0, span.seconds)
        } else if span.seconds >= -spd && 0 > span.seconds {
            (-1, span.seconds + spd)
        } else {
            (span.seconds.div_euclid(spd), span.seconds.rem_euclid(spd))
        };
        // 0 ≤ secs ≤ 86 399 + 86 400 + 1
        let secs = rem as u32 + self.second + carry;
        let (extra, second) = if secs >= 2 * SECONDS_PER_DAY {
            (2, secs - 2 * SECONDS_PER_DAY)
        } else if secs >= SECONDS_PER_DAY {
            (1, secs - SECONDS_PER_DAY)
        } else {
            (0, secs)
        };
        // |days + extra| ≤ 24 857: the sum cannot overflow, the epoch's day saturates.
        Self {
            day: self.day.saturating_add(days + extra),
            second,
            nano,
            scale: PhantomData,
        }
    }

    /// [`Epoch::add`] of a span that is not negative (the attitude node's control period,
    /// [`TimeSpan::from_seconds_f32`] of a positive number): the same epoch, in fewer bytes
    /// of MSP430 code (no branch for the negative spans, an unsigned division for a span of a
    /// day or more). A negative span is taken as its `u32` reading: the caller must not pass
    /// one.
    pub(crate) fn add_nonnegative(&self, span: TimeSpan) -> Self {
        let s = span.seconds as u32;
        let (mut days, rem) = if SECONDS_PER_DAY > s {
            (0, s)
        } else {
            (s / SECONDS_PER_DAY, s % SECONDS_PER_DAY)
        };
        // as `add`: nano < 2e9 and 0 ≤ second ≤ 86 399 + 86 400 + 1 fit u32
        let mut nano = self.nano + span.nano;
        let mut second = self.second + rem;
        if nano >= NANOS_PER_SECOND {
            nano -= NANOS_PER_SECOND;
            second += 1;
        }
        if second >= 2 * SECONDS_PER_DAY {
            second -= 2 * SECONDS_PER_DAY;
            days += 2;
        } else if second >= SECONDS_PER_DAY {
            second -= SECONDS_PER_DAY;
            days += 1;
        }
        // days ≤ 24 855 + 2: exact in i32, the epoch's day saturates as `add`'s
        Self {
            day: self.day.saturating_add(days as i32),
            second,
            nano,
            scale: PhantomData,
        }
    }

    /// Reinterprets the same calendar reading in another scale (no offset applied). Used for
    /// documented approximations such as UT1 ≈ UTC.
    pub const fn relabel<T: TimeScale>(self) -> Epoch<T> {
        Epoch {
            day: self.day,
            second: self.second,
            nano: self.nano,
            scale: PhantomData,
        }
    }
}

impl Epoch<Utc> {
    /// A UTC epoch from a TLE epoch: two-digit year (< 57 → 20yy, else 19yy, as in Vallado's
    /// `twoline2rv`), day of year (1 = 1 January) and the day fraction as an integer number of
    /// 1e-8 days (the TLE's eight decimals), which converts exactly to nanoseconds.
    pub fn from_tle_epoch(yy: u8, day_of_year: u16, frac_1e8: u32) -> Result<Self, TimeError> {
        let year = if 57 > yy {
            2000 + i32::from(yy)
        } else {
            1900 + i32::from(yy)
        };
        let days_in_year = if is_leap_year(year) { 366 } else { 365 };
        if day_of_year == 0 || day_of_year > days_in_year {
            return Err(TimeError::DayOfYear(day_of_year));
        }
        if frac_1e8 >= 100_000_000 {
            return Err(TimeError::OutOfRange);
        }
        // 1e-8 day = 864 µs = 27/31 250 s exactly: frac·27 < 2.7e9 fits u32, and the remainder
        // (< 31 250) times 32 000 ns is the nanosecond.
        let x = frac_1e8 * 27;
        let second = x / 31_250;
        let nano = (x % 31_250) * 32_000;
        let day = days_from_civil(year, 1, 1) + i32::from(day_of_year) - 1;
        Self::from_parts(day, second, nano)
    }
}

impl TimeSpan {
    /// Zero.
    pub const ZERO: Self = Self {
        seconds: 0,
        nano: 0,
    };

    fn from_seconds_nanos_i64(secs: i64, nanos: i64) -> Self {
        let total_secs = secs + nanos.div_euclid(i64::from(NANOS_PER_SECOND));
        let nano = nanos.rem_euclid(i64::from(NANOS_PER_SECOND)) as u32;
        Self {
            seconds: Ord::clamp(total_secs, i64::from(i32::MIN), i64::from(i32::MAX)) as i32,
            nano,
        }
    }

    /// A span of whole seconds (a control period, a clock step).
    pub const fn from_whole_seconds(seconds: i32) -> Self {
        Self { seconds, nano: 0 }
    }

    /// A span of `seconds` given in f32 (a control period), to the nanosecond f32 holds: exact
    /// for whole seconds; NaN gives zero, the ends saturate.
    pub fn from_seconds_f32(seconds: f32) -> Self {
        Self::new(0, (seconds * 1e9) as i64)
    }

    /// A span of whole seconds and nanoseconds (nanoseconds may be any value; they are carried).
    /// Saturates at the ends of the range (±68 years).
    pub fn new(seconds: i32, nanos: i64) -> Self {
        match i32::try_from(nanos) {
            // |nanos| < 2.2 s, the common case: i32 arithmetic (no 64-bit division).
            Ok(n) => Self {
                seconds: seconds.saturating_add(n.div_euclid(NANOS_PER_SECOND as i32)),
                nano: n.rem_euclid(NANOS_PER_SECOND as i32) as u32,
            },
            Err(_) => Self::from_seconds_nanos_i64(i64::from(seconds), nanos),
        }
    }

    /// `self` with the sign reversed (saturating at the end of the range).
    const fn negated(self) -> Self {
        if self.nano == 0 {
            Self {
                seconds: self.seconds.saturating_neg(),
                nano: 0,
            }
        } else {
            Self {
                seconds: (-1_i32).saturating_sub(self.seconds),
                nano: NANOS_PER_SECOND - self.nano,
            }
        }
    }

    /// A span from f64 seconds (host use). Non-finite or out-of-range values give an error.
    pub fn from_seconds_f64(seconds: f64) -> Result<Self, TimeError> {
        if !seconds.is_finite() || seconds.abs() > 2.0e9 {
            return Err(TimeError::OutOfRange);
        }
        let whole = libm::floor(seconds);
        let nano = libm::round((seconds - whole) * 1e9) as i64;
        Ok(Self::from_seconds_nanos_i64(whole as i64, nano))
    }

    /// A span from f64 minutes (host use, e.g. SGP4's `tsince`).
    pub fn from_minutes_f64(minutes: f64) -> Result<Self, TimeError> {
        Self::from_seconds_f64(minutes * 60.0)
    }

    /// Whole seconds (floor).
    pub const fn whole_seconds(&self) -> i32 {
        self.seconds
    }

    /// Nanoseconds above [`TimeSpan::whole_seconds`], 0..1e9.
    pub const fn nanos(&self) -> u32 {
        self.nano
    }

    /// Whole milliseconds, rounded toward zero, saturated to `i32` (i32 arithmetic only).
    fn milliseconds_toward_zero(&self) -> i32 {
        // 2 147 484 s and more is beyond i32 milliseconds.
        const LIMIT: i32 = 2_147_484;
        let ns_per_ms = 1_000_000;
        if self.seconds >= 0 {
            if self.seconds >= LIMIT {
                return i32::MAX;
            }
            (self.seconds * 1000).saturating_add((self.nano / ns_per_ms) as i32)
        } else {
            // −(a·1000 + ⌊(1e9 − nano)/1e6⌋) with a = −(seconds + 1) ≥ 0
            let a = -(self.seconds + 1);
            if a >= LIMIT {
                return i32::MIN;
            }
            (-(a * 1000)).saturating_sub(((NANOS_PER_SECOND - self.nano) / ns_per_ms) as i32)
        }
    }

    /// The span in f64 seconds (host use; exact to about 1e-7 s over decades).
    pub fn as_seconds_f64(&self) -> f64 {
        self.seconds as f64 + self.nano as f64 * 1e-9
    }

    /// The span as `(whole_minutes, remainder_minutes)` in f32: `whole_minutes` is an integer
    /// (exact in f32 up to 2^24 min = 31 years) and `remainder_minutes` is in 0..1 with a
    /// resolution of 2^-24 min (4 µs). Their sum is the span in minutes.
    pub fn split_minutes(&self) -> (f32, f32) {
        let whole = self.seconds.div_euclid(60);
        let rem_s = self.seconds.rem_euclid(60);
        let rem_min = (rem_s as f32 + self.nano as f32 * 1e-9) / 60.0;
        (whole as f32, rem_min)
    }

    /// The span as `(whole_seconds, remainder_seconds)` in f32, as [`TimeSpan::split_minutes`].
    pub fn split_seconds(&self) -> (f32, f32) {
        (self.seconds as f32, self.nano as f32 * 1e-9)
    }
}

// ---------------------------------------------------------------------------------------------
// Leap seconds: UTC → TAI → TT
// ---------------------------------------------------------------------------------------------

/// TT − TAI in nanoseconds (32.184 s, exact by definition).
pub const TT_MINUS_TAI_NS: i64 = 32_184_000_000;
/// [`TT_MINUS_TAI_NS`] as a span (built at compile time: no 64-bit division at run time).
const TT_MINUS_TAI: TimeSpan = TimeSpan {
    seconds: TT_MINUS_TAI_NS.div_euclid(NANOS_PER_SECOND as i64) as i32,
    nano: TT_MINUS_TAI_NS.rem_euclid(NANOS_PER_SECOND as i64) as u32,
};

/// The last UTC day (year, month, day) for which [`LEAP_SECONDS`] is known complete: every UTC
/// instant up to the end of this day (inclusive) has its TAI − UTC in the table.
///
/// Basis: IERS Bulletin C. The last leap second was 2016-12-31 23:59:60 (TAI − UTC = 37 s from
/// 2017-01-01). Bulletin C 70 (July 2025) announced none at the end of December 2025 (the last
/// bulletin the author checked directly); a leap second at the end of June or December 2026
/// would have been announced in Bulletin C 71 (January 2026) or C 72 (July 2026), and the
/// project's information (2026-11) is that none was. Check C 71/C 72 and extend the table and
/// this date when IERS publishes the next bulletin (C 73, January 2027).
pub const LEAP_SECONDS_VALID_UNTIL: (i32, u8, u8) = (2026, 12, 31);

/// Days since 2000-01-01 of the first UTC day after [`LEAP_SECONDS_VALID_UNTIL`].
const LEAP_TABLE_END_DAY: i32 = days_from_civil(
    LEAP_SECONDS_VALID_UNTIL.0,
    LEAP_SECONDS_VALID_UNTIL.1,
    LEAP_SECONDS_VALID_UNTIL.2,
) + 1;

/// One step of TAI − UTC: from UTC day `day` (days since 2000-01-01) 00:00:00 on, TAI − UTC is
/// `tai_minus_utc_s` seconds.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LeapSecond {
    /// The UTC day, as days since 2000-01-01, from whose 00:00:00 the offset applies.
    pub day: i32,
    /// TAI − UTC in seconds.
    pub tai_minus_utc_s: u8,
}

const fn leap(year: i32, month: u8, tai_minus_utc_s: u8) -> LeapSecond {
    LeapSecond {
        day: days_from_civil(year, month, 1),
        tai_minus_utc_s,
    }
}

/// TAI − UTC since 1972-01-01 (IERS Bulletin C; USNO `tai-utc.dat`), in date order. Each entry
/// after the first follows a positive leap second inserted as 23:59:60 of the previous day.
pub const LEAP_SECONDS: [LeapSecond; 28] = [
    leap(1972, 1, 10),
    leap(1972, 7, 11),
    leap(1973, 1, 12),
    leap(1974, 1, 13),
    leap(1975, 1, 14),
    leap(1976, 1, 15),
    leap(1977, 1, 16),
    leap(1978, 1, 17),
    leap(1979, 1, 18),
    leap(1980, 1, 19),
    leap(1981, 7, 20),
    leap(1982, 7, 21),
    leap(1983, 7, 22),
    leap(1985, 7, 23),
    leap(1988, 1, 24),
    leap(1990, 1, 25),
    leap(1991, 1, 26),
    leap(1992, 7, 27),
    leap(1993, 7, 28),
    leap(1994, 7, 29),
    leap(1996, 1, 30),
    leap(1997, 7, 31),
    leap(1999, 1, 32),
    leap(2006, 1, 33),
    leap(2009, 1, 34),
    leap(2012, 7, 35),
    leap(2015, 7, 36),
    leap(2017, 1, 37),
];

/// The table entry in force on UTC day `day`, `None` before 1972.
fn leap_entry_for_utc_day(day: i32) -> Option<LeapSecond> {
    LEAP_SECONDS.iter().rev().find(|e| day >= e.day).copied()
}

/// True if UTC day `day` ends with a leap second (its last second is 23:59:60).
fn day_has_leap_second(day: i32) -> bool {
    LEAP_SECONDS.iter().skip(1).any(|e| e.day == day + 1)
}

fn year_of_day(day: i32) -> i32 {
    civil_from_days(day).0
}

impl Epoch<Utc> {
    /// TAI − UTC at this epoch in seconds; with `extrapolate`, epochs after
    /// [`LEAP_SECONDS_VALID_UNTIL`] get the last offset instead of an error.
    fn tai_minus_utc(&self, extrapolate: bool) -> Result<u8, TimeError> {
        if !extrapolate && self.day >= LEAP_TABLE_END_DAY {
            return Err(TimeError::AfterLeapSeconds(year_of_day(self.day)));
        }
        if self.second >= SECONDS_PER_DAY && !day_has_leap_second(self.day) {
            return Err(TimeError::NotALeapSecond(self.day));
        }
        // During 23:59:60 the day's own (old) offset applies: TAI keeps counting.
        leap_entry_for_utc_day(self.day)
            .map(|e| e.tai_minus_utc_s)
            .ok_or(TimeError::BeforeLeapSeconds(year_of_day(self.day)))
    }

    /// TAI − UTC (ΔAT) at this epoch, in seconds, from [`LEAP_SECONDS`].
    ///
    /// # Errors
    /// [`TimeError::BeforeLeapSeconds`] before 1972, [`TimeError::AfterLeapSeconds`] after
    /// [`LEAP_SECONDS_VALID_UNTIL`], [`TimeError::NotALeapSecond`] for a 23:59:60 that did not
    /// exist.
    pub fn tai_minus_utc_s(&self) -> Result<u8, TimeError> {
        self.tai_minus_utc(false)
    }

    /// This UTC epoch in TAI: `TAI = UTC + ΔAT` (exact; the leap second 23:59:60 maps to its own
    /// TAI second).
    ///
    /// # Errors
    /// As [`Epoch::<Utc>::tai_minus_utc_s`].
    pub fn to_tai(&self) -> Result<Epoch<Tai>, TimeError> {
        let offset = self.tai_minus_utc(false)?;
        Ok(self.add(TimeSpan::new(i32::from(offset), 0)).relabel())
    }

    /// As [`Epoch::<Utc>::to_tai`], but after [`LEAP_SECONDS_VALID_UNTIL`] it assumes no new leap
    /// second (TAI − UTC = 37 s): at most the number of unannounced leap seconds off (none is
    /// expected before 2029; the Earth currently runs fast). For models that tolerate 1 s, such
    /// as precession, nutation and the Sun.
    ///
    /// # Errors
    /// [`TimeError::BeforeLeapSeconds`] before 1972, [`TimeError::NotALeapSecond`].
    pub fn to_tai_extrapolated(&self) -> Result<Epoch<Tai>, TimeError> {
        let offset = self.tai_minus_utc(true)?;
        Ok(self.add(TimeSpan::new(i32::from(offset), 0)).relabel())
    }

    /// This UTC epoch in TT: `TT = UTC + ΔAT + 32.184 s`.
    ///
    /// # Errors
    /// As [`Epoch::<Utc>::to_tai`].
    pub fn to_tt(&self) -> Result<Epoch<Tt>, TimeError> {
        Ok(self.plus_tt_minus_utc(self.tai_minus_utc(false)?))
    }

    /// As [`Epoch::<Utc>::to_tt`] with [`Epoch::<Utc>::to_tai_extrapolated`].
    ///
    /// # Errors
    /// As [`Epoch::<Utc>::to_tai_extrapolated`].
    pub fn to_tt_extrapolated(&self) -> Result<Epoch<Tt>, TimeError> {
        Ok(self.plus_tt_minus_utc(self.tai_minus_utc(true)?))
    }

    /// `UTC + ΔAT + 32.184 s` in one exact addition (the same epoch as adding ΔAT, then
    /// 32.184 s: both are non-negative, so the day's saturation cannot differ).
    fn plus_tt_minus_utc(&self, tai_minus_utc_s: u8) -> Epoch<Tt> {
        self.add(TimeSpan {
            seconds: i32::from(tai_minus_utc_s) + TT_MINUS_TAI.seconds,
            nano: TT_MINUS_TAI.nano,
        })
        .relabel()
    }

    /// This UTC epoch in UT1: `UT1 = UTC + DUT1`.
    ///
    /// `dut1` is UT1 − UTC from IERS Bulletin A (or the 0.1 s value broadcast in Bulletin D);
    /// `None` means UT1 ≈ UTC, a relabel whose error is |DUT1| ≤ 0.9 s (GMST then off by up to
    /// 6.6e-5 rad, 0.46 km at LEO radius). A leap second 23:59:60 keeps its reading (second
    /// 86 400), which GMST treats as 00:00:00 of the next day.
    ///
    /// # Errors
    /// [`TimeError::Dut1`] if |`dut1`| > 0.9 s.
    pub fn to_ut1(&self, dut1: Option<TimeSpan>) -> Result<Epoch<Ut1>, TimeError> {
        match dut1 {
            None => Ok(self.relabel()),
            Some(d) => {
                // |d| ≤ 0.9 s: 0 s + ≤ 0.9e9 ns, or −1 s + ≥ 0.1e9 ns.
                let within = match d.seconds {
                    0 => 900_000_000 >= d.nano,
                    -1 => d.nano >= 100_000_000,
                    _ => false,
                };
                if !within {
                    return Err(TimeError::Dut1(d.milliseconds_toward_zero()));
                }
                Ok(self.add(d).relabel())
            }
        }
    }
}

impl Epoch<Tai> {
    /// TAI → UTC, the exact inverse of [`Epoch::<Utc>::to_tai`]: the TAI second that follows
    /// 23:59:59 on the last day before a step of [`LEAP_SECONDS`] is returned as 23:59:60.
    ///
    /// # Errors
    /// [`TimeError::BeforeLeapSeconds`] before 1972-01-01 00:00:10 TAI,
    /// [`TimeError::AfterLeapSeconds`] after [`LEAP_SECONDS_VALID_UNTIL`].
    pub fn to_utc(&self) -> Result<Epoch<Utc>, TimeError> {
        self.utc_with_policy(false)
    }

    /// As [`Epoch::<Tai>::to_utc`], assuming no leap second after [`LEAP_SECONDS_VALID_UNTIL`].
    ///
    /// # Errors
    /// [`TimeError::BeforeLeapSeconds`].
    pub fn to_utc_extrapolated(&self) -> Result<Epoch<Utc>, TimeError> {
        self.utc_with_policy(true)
    }

    fn utc_with_policy(&self, extrapolate: bool) -> Result<Epoch<Utc>, TimeError> {
        // The entry whose start, expressed in TAI (UTC day start + its offset), is not after self.
        let start_tai = |e: &LeapSecond| -> Epoch<Tai> {
            Epoch::<Tai> {
                day: e.day,
                second: 0,
                nano: 0,
                scale: PhantomData,
            }
            .add(TimeSpan::new(i32::from(e.tai_minus_utc_s), 0))
        };
        let index = LEAP_SECONDS
            .iter()
            .rposition(|e| *self >= start_tai(e))
            .ok_or(TimeError::BeforeLeapSeconds(year_of_day(self.day)))?;
        let entry = LEAP_SECONDS
            .get(index)
            .copied()
            .ok_or(TimeError::OutOfRange)?;
        let utc: Epoch<Utc> = self
            .add(TimeSpan::new(-i32::from(entry.tai_minus_utc_s), 0))
            .relabel();
        if !extrapolate && utc.day >= LEAP_TABLE_END_DAY {
            return Err(TimeError::AfterLeapSeconds(year_of_day(utc.day)));
        }
        // Within the second before the next step: that is the leap second 23:59:60.
        if let Some(next) = LEAP_SECONDS.get(index + 1) {
            let leap_start = start_tai(next).add(TimeSpan::new(-1, 0));
            if *self >= leap_start {
                return Ok(Epoch {
                    day: next.day - 1,
                    second: SECONDS_PER_DAY,
                    nano: self.nano,
                    scale: PhantomData,
                });
            }
        }
        Ok(utc)
    }

    /// TAI → TT (`TT = TAI + 32.184 s`, exact).
    pub fn to_tt(&self) -> Epoch<Tt> {
        self.add(TT_MINUS_TAI).relabel()
    }
}

impl Epoch<Tt> {
    /// TT → TAI (`TAI = TT − 32.184 s`, exact).
    pub fn to_tai(&self) -> Epoch<Tai> {
        self.add(TT_MINUS_TAI.negated()).relabel()
    }
}

// ---------------------------------------------------------------------------------------------
// Julian date, day number, decimal year
// ---------------------------------------------------------------------------------------------

/// Julian date of a calendar date and time, Vallado 2013 algorithm 14 (`jday`), as the pair
/// `(jd, jd_frac)`: `jd` ends in .5 (the preceding midnight) and `jd_frac` in 0..1 is the day
/// fraction (Vallado 2013 keeps the same split to preserve precision).
///
/// ```text
/// JD = 367·y − ⌊7(y + ⌊(mon + 9)/12⌋)/4⌋ + ⌊275·mon/9⌋ + day + 1 721 013.5
/// jd_frac = (sec + 60·min + 3600·hr) / 86 400
/// ```
/// Valid 1900-03-01 … 2100-02-28 (the formula omits the century rule); the calendar is checked
/// as in [`Epoch::from_calendar`]. Equal to [`Epoch::jd_split`] of the same reading (tested).
///
/// # Errors
/// As [`Epoch::from_calendar`].
pub fn jday(c: &Calendar) -> Result<(f64, f64), TimeError> {
    Epoch::<Utc>::from_calendar(*c)?;
    let year = f64::from(c.year);
    let mon = f64::from(c.month);
    let jd = 367.0 * year - libm::floor(7.0 * (year + libm::floor((mon + 9.0) / 12.0)) * 0.25)
        + libm::floor(275.0 * mon / 9.0)
        + f64::from(c.day)
        + 1_721_013.5;
    let sec = f64::from(c.second) + f64::from(c.nano) * 1e-9;
    let jd_frac = (sec + f64::from(c.minute) * 60.0 + f64::from(c.hour) * 3600.0)
        / f64::from(SECONDS_PER_DAY);
    // 23:59:60 gives jd_frac ≥ 1: carry whole days as Vallado does.
    let carry = libm::floor(jd_frac);
    Ok((jd + carry, jd_frac - carry))
}

impl<S: TimeScale> Epoch<S> {
    /// An epoch from a split Julian date `jd_whole + jd_frac` (either part may hold any share of
    /// the date), rounded to the nearest nanosecond. Inverse of [`Epoch::jd_split`] and [`jday`].
    ///
    /// # Errors
    /// [`TimeError::OutOfRange`] for non-finite values or a date outside the years
    /// [`Epoch::MIN_YEAR`]..=[`Epoch::MAX_YEAR`].
    pub fn from_jd_split(jd_whole: f64, jd_frac: f64) -> Result<Self, TimeError> {
        if !jd_whole.is_finite() || !jd_frac.is_finite() {
            return Err(TimeError::OutOfRange);
        }
        let min_day = f64::from(days_from_civil(Self::MIN_YEAR, 1, 1));
        let max_day = f64::from(days_from_civil(Self::MAX_YEAR, 12, 31));
        // Days since 2000-01-01 00:00 as whole + fraction, each part exact in f64.
        let w = jd_whole - JD_DAY0;
        let w_whole = libm::floor(w);
        let f = (w - w_whole) + jd_frac;
        let f_whole = libm::floor(f);
        let day_f = w_whole + f_whole;
        let frac = f - f_whole;
        if !(day_f >= min_day && max_day >= day_f) {
            return Err(TimeError::OutOfRange);
        }
        let ns_per_day = i64::from(SECONDS_PER_DAY) * i64::from(NANOS_PER_SECOND);
        let ns = libm::round(frac * ns_per_day as f64) as i64;
        let start = Self {
            day: day_f as i32,
            second: 0,
            nano: 0,
            scale: PhantomData,
        };
        let secs = ns.div_euclid(i64::from(NANOS_PER_SECOND));
        let nano = ns.rem_euclid(i64::from(NANOS_PER_SECOND));
        Ok(start.add(TimeSpan::new(secs as i32, nano)))
    }

    /// Seed 000's day number `d` (eq. 7.1, Schlyter's), as `(whole_days, day_fraction)` in f32:
    /// days since 1999-12-31 00:00 of this scale, i.e. `d = JD − 2 451 543.5`
    /// (note 000 §2: d = 3455.0 on 2009-06-16 00:00). `whole_days` is an integer and
    /// `day_fraction` is in 0..=1 (1 only during a leap second), resolution 6e-8 day (5 ms).
    ///
    /// Eq. 7.1 evaluates `367·Y − 7(Y + (M + 9)/12)/4 + 275·M/9 + D − 730 530` with integer
    /// divisions, equal to this for 1900-03-01 … 2100-02-28 (tested); this function is exact for
    /// every supported date.
    pub fn day_number_split(&self) -> (f32, f32) {
        ((self.day + 1) as f32, self.day_fraction_f32())
    }

    /// The decimal year as `(year, fraction)`: `fraction` = (day of year − 1 + day fraction) /
    /// days in the year, f32 (resolution 6e-8 yr = 2 s), in 0..1 (it may round to 1.0 in the
    /// year's last second). The convention of IGRF's
    /// `decimal_year` input.
    ///
    /// The year and the day of the year come from [`year_from_days`] (the year of
    /// [`civil_from_days`] without its month and day).
    pub fn decimal_year_split(&self) -> (i32, f32) {
        let (year, day_of_year, leap) = year_from_days(self.day);
        let days_in_year: f32 = if leap { 366.0 } else { 365.0 };
        let fraction = (f32::from(day_of_year) + self.day_fraction_f32()) / days_in_year;
        (year, fraction)
    }

    /// The decimal year in f32 (e.g. 2009.4548), resolution 1.2e-4 yr (1.1 h) around 2000: for
    /// slowly varying models such as IGRF (secular variation < 200 nT/yr → < 0.03 nT).
    pub fn decimal_year_f32(&self) -> f32 {
        let (year, fraction) = self.decimal_year_split();
        year as f32 + fraction
    }
}

// ---------------------------------------------------------------------------------------------
// GMST, IAU-82
// ---------------------------------------------------------------------------------------------

/// One revolution in binary-angle units (2^64).
const REV_BAM: f64 = 18_446_744_073_709_551_616.0;
/// GMST at J2000.0 (2000-01-01 12:00 UT1), seconds of sidereal time (Vallado 2013 eq. 3-45).
const GMST_J2000_S: f64 = 67_310.548_41;
/// Excess of the sidereal over the solar day, revolutions per UT1 day:
/// 8 640 184.812 866 s per Julian century / 36 525 days / 86 400 s per revolution
/// (so 360.985 647 366 29°/day = 360° + 0.985 647 366 29°).
const SIDEREAL_EXCESS_REV_PER_DAY: f64 = 8_640_184.812_866 / 36_525.0 / 86_400.0;
/// GMST at 2000-01-01 00:00 UT1 (half a day before J2000.0), revolutions.
const GMST_DAY0_REV: f64 = GMST_J2000_S / 86_400.0 - 0.5 * (1.0 + SIDEREAL_EXCESS_REV_PER_DAY);
/// [`GMST_DAY0_REV`] (0.277 688 3 rev) as a binary angle (2^64 = one revolution).
const GMST_DAY0_BAM: u64 = (GMST_DAY0_REV * REV_BAM) as u64;
/// GMST advance per whole UT1 day, modulo a revolution, as a binary angle.
const GMST_PER_DAY_BAM: u64 = (SIDEREAL_EXCESS_REV_PER_DAY * REV_BAM) as u64;
/// GMST advance per UT1 second as a binary angle (1.002 737 909 35 rev / 86 400 s).
const GMST_PER_SECOND_BAM: u64 =
    ((1.0 + SIDEREAL_EXCESS_REV_PER_DAY) / 86_400.0 * REV_BAM + 0.5) as u64;
/// GMST advance per UT1 microsecond as a binary angle (rounding: < 2e-16 rad per 1e6 µs).
const GMST_PER_MICRO_BAM: u64 =
    ((1.0 + SIDEREAL_EXCESS_REV_PER_DAY) / 86_400.0e6 * REV_BAM + 0.5) as u64;
/// GMST advance per UT1 nanosecond as a binary angle (rounding: < 2e-16 rad per 1000 ns).
const GMST_PER_NANO_BAM: u64 =
    ((1.0 + SIDEREAL_EXCESS_REV_PER_DAY) / 86_400.0e9 * REV_BAM + 0.5) as u64;
/// 2π · 2^29, rounded (relative error 1.5e-10): a 32-bit binary angle times this is radians·2^61.
const TWO_PI_Q29: u32 = 3_373_259_426;

// The nanosecond term is formed in one 32-bit product: (nano mod 1000) · GMST_PER_NANO_BAM < 2^32.
const _: () = assert!(1 << 32 > GMST_PER_NANO_BAM * 1000 && 1 << 32 > GMST_PER_MICRO_BAM);

/// A 64-bit integer as two 32-bit words, for exact wrapping fixed point on a 16-bit core: the
/// MSP430 has no 64-bit arithmetic (a `u64` product is a library call of about 900 cycles, a
/// division 3.4 KB of code), so products are formed from 16 × 16 → 32-bit pieces here.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) struct Wide {
    hi: u32,
    lo: u32,
}

impl Wide {
    /// Zero.
    pub(crate) const ZERO: Self = Self { hi: 0, lo: 0 };

    /// From a `u64` (compile-time constants).
    pub(crate) const fn from_u64(x: u64) -> Self {
        Self {
            hi: (x >> 32) as u32,
            lo: x as u32,
        }
    }

    /// As a `u64` (host code and tests).
    pub(crate) const fn to_u64(self) -> u64 {
        ((self.hi as u64) << 32) | self.lo as u64
    }

    /// The high word (bits 32..=63).
    pub(crate) const fn hi(self) -> u32 {
        self.hi
    }

    /// The low word (bits 0..=31).
    pub(crate) const fn lo(self) -> u32 {
        self.lo
    }

    /// `self + other` modulo 2^64 (out of line on the MSP430: 0.3 KB less for its 6 uses).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    pub(crate) fn wrapping_add(self, other: Self) -> Self {
        let (lo, carry) = self.lo.overflowing_add(other.lo);
        Self {
            hi: self
                .hi
                .wrapping_add(other.hi)
                .wrapping_add(u32::from(carry)),
            lo,
        }
    }

    /// `−self` modulo 2^64.
    fn wrapping_neg(self) -> Self {
        Self::ZERO.wrapping_sub(self)
    }

    /// `self − other` modulo 2^64.
    fn wrapping_sub(self, other: Self) -> Self {
        let (lo, borrow) = self.lo.overflowing_sub(other.lo);
        Self {
            hi: self
                .hi
                .wrapping_sub(other.hi)
                .wrapping_sub(u32::from(borrow)),
            lo,
        }
    }

    /// The full 64-bit product `a·b`, from four 16 × 16 → 32-bit products.
    #[cfg_attr(target_arch = "msp430", inline(never))]
    pub(crate) fn mul_u32(a: u32, b: u32) -> Self {
        let (a1, a0) = (a >> 16, a & 0xFFFF);
        let (b1, b0) = (b >> 16, b & 0xFFFF);
        let low = a0 * b0;
        let (mid, mid_carry) = (a1 * b0).overflowing_add(a0 * b1);
        let lo = low.wrapping_add(mid << 16);
        let hi = (a1 * b1)
            .wrapping_add(mid >> 16)
            .wrapping_add(u32::from(mid_carry) << 16)
            .wrapping_add(u32::from(low > lo));
        Self { hi, lo }
    }

    /// `self·v` modulo 2^64, `v` unsigned.
    pub(crate) fn wrapping_mul_u32(self, v: u32) -> Self {
        let p = Self::mul_u32(self.lo, v);
        Self {
            hi: p.hi.wrapping_add(self.hi.wrapping_mul(v)),
            lo: p.lo,
        }
    }

    /// `self·v` modulo 2^64, `v` sign-extended (as `(self as i64).wrapping_mul(v as i64)`).
    pub(crate) fn wrapping_mul_i32(self, v: i32) -> Self {
        let p = self.wrapping_mul_u32(v as u32);
        // v < 0 is v + 2^32 − 2^32 as an unsigned word: subtract self·2^32.
        if 0 > v {
            Self {
                hi: p.hi.wrapping_sub(self.lo),
                lo: p.lo,
            }
        } else {
            p
        }
    }

    /// `x as i64` (truncation toward zero, saturating, NaN → 0), from the bits of `x`: no
    /// float-to-64-bit library call.
    fn from_f32_as_i64(x: f32) -> Self {
        let bits = x.to_bits();
        let exp = (bits >> 23) & 0xFF;
        if x.is_nan() || 127 > exp {
            // NaN, or |x| < 1
            return Self::ZERO;
        }
        let negative = bits >> 31 != 0;
        if exp >= 127 + 63 {
            // |x| ≥ 2^63 (infinities included): saturated
            return if negative {
                Self::from_u64(1 << 63)
            } else {
                Self::from_u64(u64::MAX >> 1)
            };
        }
        // |x| = m·2^k with −23 ≤ k ≤ 39
        let m = (bits & 0x007F_FFFF) | 0x0080_0000;
        let k = exp as i32 - 150;
        let magnitude = if 0 > k {
            Self { hi: 0, lo: m >> -k }
        } else if k == 0 {
            Self { hi: 0, lo: m }
        } else if 32 > k {
            Self {
                hi: m >> (32 - k),
                lo: m << k,
            }
        } else {
            Self {
                hi: m << (k - 32),
                lo: 0,
            }
        };
        if negative {
            magnitude.wrapping_neg()
        } else {
            magnitude
        }
    }

    /// `self·2^-61` rounded to f32 (nearest, ties to even), as `self as f32 * 2^-61` rounds it,
    /// for `self` zero or at least 2^31 (so that the result is a normal number).
    fn times_2_pow_minus_61_to_f32(self) -> f32 {
        let (mut hi, mut lo) = (self.hi, self.lo);
        // e: the exponent of the leading bit minus 63
        let mut e: u32 = 128;
        if hi == 0 {
            if lo == 0 {
                return 0.0;
            }
            hi = lo;
            lo = 0;
            e -= 32;
        }
        // Normalise (at most 31 steps: hi ≠ 0).
        while hi & 0x8000_0000 == 0 {
            hi = (hi << 1) | (lo >> 31);
            lo <<= 1;
            e -= 1;
        }
        // 24 significant bits, then the rounding bit and the sticky bits below it. The leading
        // bit of the significand adds one to the exponent field: (e − 63 + 63 − 61 + 127) − 1.
        let significand = hi >> 8;
        let mut bits = (e << 23) + significand;
        if hi & 0x80 != 0 && ((hi & 0x7F) | lo != 0 || significand & 1 != 0) {
            bits += 1;
        }
        f32::from_bits(bits)
    }
}

/// The linear part of GMST (everything but the T² and T³ terms) as a binary angle, 2^64 = one
/// revolution, so the reduction modulo 2π is exact wrapping; in 32-bit words (see [`Wide`]).
fn gmst_linear(ut1: &Epoch<Ut1>) -> Wide {
    // nano < 1e9: the microseconds and nanoseconds below them, each times its rounded rate
    let micro = ut1.nano / 1000;
    let nano = ut1.nano - micro * 1000;
    Wide::from_u64(GMST_DAY0_BAM)
        .wrapping_add(Wide::from_u64(GMST_PER_DAY_BAM).wrapping_mul_i32(ut1.day))
        .wrapping_add(Wide::from_u64(GMST_PER_SECOND_BAM).wrapping_mul_u32(ut1.second))
        .wrapping_add(Wide::mul_u32(GMST_PER_MICRO_BAM as u32, micro))
        .wrapping_add(Wide {
            hi: 0,
            lo: GMST_PER_NANO_BAM as u32 * nano,
        })
}

/// Greenwich mean sidereal time θ_GMST (IAU-82) in radians, 0..=2π, f32, for flight code.
///
/// Vallado 2013 eq. 3-45 / algorithm 15 (`gstime`), from the IAU-1982 expression of
/// Aoki et al. (1982):
/// ```text
/// T = (JD_UT1 − 2 451 545.0) / 36 525
/// θ_GMST = 67 310.548 41 s + (876 600 h + 8 640 184.812 866 s)·T + 0.093 104 s·T² − 6.2e-6 s·T³
/// ```
/// The linear part is evaluated exactly from the epoch's integer day, second and nanosecond in
/// a 64-bit binary angle (2^64 = 2π, so reducing modulo 2π is integer wrap-around; the
/// 876 600 h·T term is a whole number of revolutions per day and vanishes), held in two 32-bit
/// words and formed from 16 × 16-bit products (no 64-bit library call on the MSP430); the small
/// T² and T³ terms are added in f32. The result is rounded to f32 once.
///
/// Accuracy: measured against an f64 `gstime` over 1990–2050 (200 000 instants), max
/// 2.40e-7 rad (half an f32 ulp near 2π), RMS 9.2e-8 rad
/// (`cargo test --test time gmst -- --nocapture`). The model itself (IAU-82, UT1) is
/// within ~0.1 mas/yr of the Earth rotation angle definitions in use since 2003; using UTC for
/// UT1 costs up to 6.6e-5 rad (see [`Epoch::<Utc>::to_ut1`]).
#[cfg_attr(target_arch = "msp430", inline(never))]
pub fn gmst_rad(ut1: &Epoch<Ut1>) -> f32 {
    let (whole, fraction) = ut1.days_since_j2000_split();
    let t = (whole + fraction) / 36_525.0;
    // 0.093 104 s·T² − 6.2e-6 s·T³, as revolutions, as a binary angle (|·| < 2e14 for |T| < 1).
    let quadratic_rev = (0.093_104 * t * t - 6.2e-6 * t * t * t) / 86_400.0;
    let quadratic = Wide::from_f32_as_i64(quadratic_rev * REV_BAM as f32);
    let bam = gmst_linear(ut1).wrapping_add(quadratic);
    // Top 32 bits × 2π·2^29 = radians · 2^61 (≥ 2^31 unless zero), then one rounding to f32.
    Wide::mul_u32(bam.hi, TWO_PI_Q29).times_2_pow_minus_61_to_f32()
}

/// Greenwich mean sidereal time (IAU-82) in radians, 0..2π, f64, for host code and one-time
/// initialisation (SGP4's `gsto`). Same algorithm as [`gmst_rad`], rounded to f64 instead:
/// error ~1e-15 rad against the exact formula (measured against an f64 `gstime` fed a split
/// Julian date, 1990–2050: max 4.9e-11 rad, the reference's own rounding; against `gstime` fed
/// one f64 Julian date, as in note 000 §2, up to 1.5e-9 rad, that date's resolution).
pub fn gmst_rad_f64(ut1: &Epoch<Ut1>) -> f64 {
    let (jd_whole, jd_frac) = ut1.jd_split();
    let t = ((jd_whole - 2_451_545.0) + jd_frac) / 36_525.0;
    let quadratic_rev = (0.093_104 * t * t - 6.2e-6 * t * t * t) / 86_400.0;
    let quadratic_bam = (quadratic_rev * REV_BAM) as i64;
    let bam = gmst_linear(ut1).to_u64().wrapping_add_signed(quadratic_bam);
    bam as f64 * (core::f64::consts::TAU / REV_BAM)
}

#[cfg(test)]
mod tests {
    //! The 32-bit arithmetic against the 64-bit formulas it replaced (kept here as references).
    use super::*;

    /// xorshift64*: deterministic test inputs.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
        }
        fn i32(&mut self) -> i32 {
            // every magnitude: a random word shifted right by 0..31 bits
            let r = self.next();
            ((r >> 32) as i32) >> (r % 32)
        }
    }

    fn days_from_civil_i64(year: i32, month: u8, day: u8) -> i32 {
        let year = i64::from(year);
        let y = if month <= 2 { year - 1 } else { year };
        let era = if y >= 0 { y } else { y - 399 } / 400;
        let yoe = y - era * 400;
        let m = i64::from(month);
        let mp = if m > 2 { m - 3 } else { m + 9 };
        let doy = (153 * mp + 2) / 5 + i64::from(day) - 1;
        let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
        let days = era * 146_097 + doe - 719_468 - 10_957;
        days.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32
    }

    fn civil_from_days_i64(days: i32) -> (i32, u8, u8) {
        let z = i64::from(days) + 10_957 + 719_468;
        let era = if z >= 0 { z } else { z - 146_096 } / 146_097;
        let doe = z - era * 146_097;
        let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
        let y = yoe + era * 400;
        let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
        let mp = (5 * doy + 2) / 153;
        let d = doy - (153 * mp + 2) / 5 + 1;
        let m = if mp < 10 { mp + 3 } else { mp - 9 };
        let year = if m <= 2 { y + 1 } else { y };
        (year as i32, m as u8, d as u8)
    }

    #[test]
    fn calendar_in_i32_equals_i64() {
        let mut rng = Rng(0x1234_5678_9abc_def1);
        let years = [
            i32::MIN,
            i32::MIN + 1,
            -5_879_611,
            -5_879_610,
            5_879_609,
            5_879_610,
        ];
        for i in 0..200_000 {
            let year = match i {
                0..=5 => years[i],
                6..=15 => i32::MAX - (i as i32 - 6),
                _ if i % 2 == 0 => 1600 + (rng.next() % 800) as i32,
                _ => rng.i32(),
            };
            let month = (rng.next() % 14) as u8;
            let day = (rng.next() % 33) as u8;
            assert_eq!(
                days_from_civil(year, month, day),
                days_from_civil_i64(year, month, day),
                "{year}-{month}-{day}"
            );
            let extreme = [i32::MIN, i32::MAX, 0, -1];
            let days = match i {
                0..=3 => extreme[i],
                _ if i % 2 == 0 => (rng.next() % 200_000) as i32 - 100_000,
                _ => rng.i32(),
            };
            assert_eq!(civil_from_days(days), civil_from_days_i64(days), "{days}");
        }
        // every month boundary 1899..2101 round trips
        for year in 1899..=2101 {
            for month in 1..=12u8 {
                let d = days_from_civil(year, month, 1);
                assert_eq!(civil_from_days(d), (year, month, 1));
            }
        }
    }

    /// `year_from_days` is the year of `civil_from_days`, the day's index from its 1 January and
    /// its leap flag, over every day of years −1000..3000 and random day counts (the first 193
    /// day counts of the `i32` range aside: there `days_from_civil(year, 1, 1)` saturates).
    #[test]
    fn year_from_days_is_the_civil_year() {
        let check = |days: i32| {
            let (year, _, _) = civil_from_days(days);
            let first = days_from_civil(year, 1, 1);
            let expected = (year, (days - first) as u16, is_leap_year(year));
            assert_eq!(year_from_days(days), expected, "{days}");
        };
        for days in days_from_civil(-1000, 1, 1)..days_from_civil(3000, 1, 1) {
            check(days);
        }
        let mut rng = Rng(0x2026_1128_0000_0001);
        for _ in 0..1_000_000 {
            let days = rng.i32();
            if days > i32::MIN + 193 {
                check(days);
            }
        }
        check(i32::MAX);
    }

    fn add_i64<S: TimeScale>(e: &Epoch<S>, span: TimeSpan) -> Epoch<S> {
        let mut nano = i64::from(e.nano) + i64::from(span.nano);
        let mut secs = i64::from(e.second) + i64::from(span.seconds);
        if nano >= i64::from(NANOS_PER_SECOND) {
            nano -= i64::from(NANOS_PER_SECOND);
            secs += 1;
        }
        let spd = i64::from(SECONDS_PER_DAY);
        let day = i64::from(e.day) + secs.div_euclid(spd);
        Epoch {
            day: day.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32,
            second: secs.rem_euclid(spd) as u32,
            nano: nano as u32,
            scale: PhantomData,
        }
    }

    fn span_i64<S: TimeScale>(later: &Epoch<S>, earlier: &Epoch<S>) -> TimeSpan {
        let days = i64::from(later.day) - i64::from(earlier.day);
        let secs =
            days * i64::from(SECONDS_PER_DAY) + i64::from(later.second) - i64::from(earlier.second);
        let nanos = i64::from(later.nano) - i64::from(earlier.nano);
        TimeSpan::from_seconds_nanos_i64(secs, nanos)
    }

    #[test]
    fn epoch_arithmetic_in_i32_equals_i64() {
        let mut rng = Rng(0xfeed_beef_0bad_cafe);
        let epoch = |rng: &mut Rng, i: u32| {
            let day = match i % 5 {
                0 => rng.i32(),
                1 => i32::MAX - (rng.next() % 3) as i32,
                2 => i32::MIN + (rng.next() % 3) as i32,
                _ => (rng.next() % 100_000) as i32 - 50_000,
            };
            let second = match rng.next() % 4 {
                0 => 86_400,
                1 => 0,
                _ => (rng.next() % 86_400) as u32,
            };
            let nano = match rng.next() % 4 {
                0 => 0,
                1 => 999_999_999,
                _ => (rng.next() % 1_000_000_000) as u32,
            };
            Epoch::<Tai>::from_parts(day, second, nano).unwrap()
        };
        for i in 0..300_000 {
            let a = epoch(&mut rng, i);
            let b = epoch(&mut rng, i / 7);
            assert_eq!(a.span_since(&b), span_i64(&a, &b), "{a:?} − {b:?}");
            let seconds = match i % 4 {
                0 => rng.i32(),
                1 => i32::MAX - (rng.next() % 3) as i32,
                2 => i32::MIN + (rng.next() % 3) as i32,
                _ => (rng.next() % 400_000) as i32 - 200_000,
            };
            let span = TimeSpan {
                seconds,
                nano: (rng.next() % 1_000_000_000) as u32,
            };
            assert_eq!(a.add(span), add_i64(&a, span), "{a:?} + {span:?}");
            let nanos = (rng.next() as i64) >> (rng.next() % 64);
            assert_eq!(
                TimeSpan::new(seconds, nanos),
                TimeSpan::from_seconds_nanos_i64(i64::from(seconds), nanos),
                "{seconds} s + {nanos} ns"
            );
            let ns = i64::from(span.seconds) * 1_000_000_000 + i64::from(span.nano);
            let ms = (ns / 1_000_000).clamp(i64::from(i32::MIN), i64::from(i32::MAX));
            assert_eq!(span.milliseconds_toward_zero(), ms as i32, "{span:?}");
        }
        assert_eq!(
            TT_MINUS_TAI.negated(),
            TimeSpan::from_seconds_nanos_i64(0, -TT_MINUS_TAI_NS)
        );
    }

    /// UTC → TT in one addition equals UTC → TAI → TT (leap seconds and saturated days included).
    #[test]
    fn utc_to_tt_in_one_addition() {
        let mut rng = Rng(0x7777_1234_abcd_0001);
        for i in 0..100_000 {
            let day = match i % 4 {
                0 => rng.i32(),
                1 => i32::MAX - (rng.next() % 3) as i32,
                _ => (rng.next() % 30_000) as i32 - 10_000,
            };
            let second = (rng.next() % 86_401) as u32;
            let nano = (rng.next() % 1_000_000_000) as u32;
            let e = Epoch::<Utc>::from_parts(day, second, nano).unwrap();
            assert_eq!(e.to_tt(), e.to_tai().map(|t| t.to_tt()), "{e:?}");
            assert_eq!(
                e.to_tt_extrapolated(),
                e.to_tai_extrapolated().map(|t| t.to_tt()),
                "{e:?}"
            );
        }
        for entry in LEAP_SECONDS.iter().skip(1) {
            let leap = Epoch::<Utc>::from_parts(entry.day - 1, SECONDS_PER_DAY, 5).unwrap();
            assert_eq!(leap.to_tt(), leap.to_tai().map(|t| t.to_tt()));
        }
    }

    #[test]
    fn tle_epoch_fraction_in_u32_equals_u64() {
        for frac in (0..100_000_000u32)
            .step_by(9_973)
            .chain([99_999_999, 1, 2, 3])
        {
            let e = Epoch::from_tle_epoch(24, 1, frac).unwrap();
            let total_ns = u64::from(frac) * 864_000;
            assert_eq!(u64::from(e.second_of_day()), total_ns / 1_000_000_000);
            assert_eq!(u64::from(e.nano()), total_ns % 1_000_000_000);
        }
    }

    #[test]
    fn wide_words_equal_u64() {
        let mut rng = Rng(0x0dd_ba11_5eed_1234);
        for _ in 0..200_000 {
            let (x, y) = (rng.next(), rng.next());
            let (a, b) = (x as u32 >> (y % 32), (x >> 32) as u32 >> (y / 32 % 32));
            assert_eq!(Wide::mul_u32(a, b).to_u64(), u64::from(a) * u64::from(b));
            let w = Wide::from_u64(y);
            assert_eq!(w.wrapping_mul_u32(a).to_u64(), y.wrapping_mul(u64::from(a)));
            let v = a as i32;
            assert_eq!(
                w.wrapping_mul_i32(v).to_u64(),
                (y as i64).wrapping_mul(i64::from(v)) as u64
            );
            assert_eq!(
                w.wrapping_add(Wide::from_u64(x)).to_u64(),
                y.wrapping_add(x)
            );
            assert_eq!(w.wrapping_neg().to_u64(), y.wrapping_neg());
            let f = f32::from_bits(x as u32);
            assert_eq!(Wide::from_f32_as_i64(f).to_u64(), f as i64 as u64, "{f:e}");
            let p = Wide::from_u64(x | 1 << 31);
            assert_eq!(
                p.times_2_pow_minus_61_to_f32().to_bits(),
                ((x | 1 << 31) as f32 * (1.0 / 2_305_843_009_213_693_952.0)).to_bits()
            );
        }
        assert_eq!(Wide::ZERO.times_2_pow_minus_61_to_f32().to_bits(), 0);
        for f in [
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            9.3e18,
            -9.3e18,
            -0.99,
            0.99,
        ] {
            assert_eq!(Wide::from_f32_as_i64(f).to_u64(), f as i64 as u64, "{f:e}");
        }
    }

    /// `gmst_rad` as it was computed with `u64` arithmetic.
    fn gmst_rad_u64(ut1: &Epoch<Ut1>) -> f32 {
        let day = i64::from(ut1.day) as u64;
        let linear = GMST_DAY0_BAM
            .wrapping_add(GMST_PER_DAY_BAM.wrapping_mul(day))
            .wrapping_add(GMST_PER_SECOND_BAM.wrapping_mul(u64::from(ut1.second)))
            .wrapping_add(GMST_PER_MICRO_BAM.wrapping_mul(u64::from(ut1.nano / 1000)))
            .wrapping_add(GMST_PER_NANO_BAM.wrapping_mul(u64::from(ut1.nano % 1000)));
        let (whole, fraction) = ut1.days_since_j2000_split();
        let t = (whole + fraction) / 36_525.0;
        let quadratic_rev = (0.093_104 * t * t - 6.2e-6 * t * t * t) / 86_400.0;
        let quadratic_bam = (quadratic_rev * REV_BAM as f32) as i64;
        let bam = linear.wrapping_add_signed(quadratic_bam);
        let q61 = (bam >> 32) * u64::from(TWO_PI_Q29);
        q61 as f32 * (1.0 / 2_305_843_009_213_693_952.0)
    }

    #[test]
    fn gmst_in_32_bit_words_is_bit_identical() {
        let mut rng = Rng(0x5eed_0000_1111_2222);
        for i in 0..300_000 {
            let day = match i % 3 {
                0 => rng.i32(),
                _ => (rng.next() % 80_000) as i32 - 40_000,
            };
            let second = (rng.next() % 86_401) as u32;
            let nano = (rng.next() % 1_000_000_000) as u32;
            let e = Epoch::<Ut1>::from_parts(day, second, nano).unwrap();
            assert_eq!(gmst_rad(&e).to_bits(), gmst_rad_u64(&e).to_bits(), "{e:?}");
        }
    }

    /// [`Epoch::add_nonnegative`] is [`Epoch::add`] for every span that is not negative: random
    /// epochs (leap seconds included) and spans of every magnitude, and the ends.
    #[test]
    fn add_nonnegative_is_add() {
        let mut rng = Rng(0x5EED_0ADD);
        let days = [
            i32::MIN,
            i32::MIN + 1,
            -24_857,
            -1,
            0,
            1,
            24_857,
            i32::MAX - 3,
            i32::MAX,
        ];
        let seconds = [
            0,
            1,
            86_399,
            86_400,
            86_401,
            172_799,
            172_800,
            i32::MAX - 1,
            i32::MAX,
        ];
        let check = |e: Epoch<Utc>, span: TimeSpan| {
            assert_eq!(e.add_nonnegative(span), e.add(span), "{e:?} + {span:?}");
        };
        for day in days {
            for second in [0, 1, 43_200, 86_399, 86_400] {
                for nano in [0, 1, 999_999_999] {
                    let e = Epoch::<Utc>::from_parts(day, second, nano).unwrap();
                    for s in seconds {
                        for n in [0, 1, 500_000_000, 999_999_999] {
                            check(
                                e,
                                TimeSpan {
                                    seconds: s,
                                    nano: n,
                                },
                            );
                        }
                    }
                }
            }
        }
        for _ in 0..1_000_000 {
            let day = rng.i32();
            let second = (rng.next() % 86_401) as u32;
            let nano = (rng.next() % u64::from(NANOS_PER_SECOND)) as u32;
            let e = Epoch::<Utc>::from_parts(day, second, nano).unwrap();
            let span = TimeSpan {
                seconds: rng.i32().checked_abs().unwrap_or(i32::MAX),
                nano: (rng.next() % u64::from(NANOS_PER_SECOND)) as u32,
            };
            check(e, span);
        }
    }

    /// [`Epoch::seconds_since_f32_small`] gives [`Epoch::seconds_since_f32`]'s bits: random
    /// pairs of epochs (leap seconds included) at every distance, and the ends.
    #[test]
    fn seconds_since_small_is_seconds_since() {
        let mut rng = Rng(0x5EED_5117);
        let days = [
            i32::MIN,
            i32::MIN + 1,
            -24_857,
            -24_856,
            -24_855,
            -1,
            0,
            1,
            24_855,
            24_856,
            24_857,
            i32::MAX - 1,
            i32::MAX,
        ];
        let check = |a: Epoch<Utc>, b: Epoch<Utc>| {
            assert_eq!(
                a.seconds_since_f32_small(&b).to_bits(),
                a.seconds_since_f32(&b).to_bits(),
                "{a:?} since {b:?}"
            );
        };
        let ends = |day: i32| {
            [
                (0, 0),
                (0, 999_999_999),
                (86_399, 5),
                (86_400, 0),
                (86_400, 999_999_999),
            ]
            .map(|(second, nano)| Epoch::<Utc>::from_parts(day, second, nano).unwrap())
        };
        for a in days {
            for b in days {
                for x in ends(a) {
                    for y in ends(b) {
                        check(x, y);
                    }
                }
            }
        }
        for _ in 0..1_000_000 {
            let epoch = |rng: &mut Rng, near: Option<i32>| {
                let day = match near {
                    Some(d) => d.wrapping_add((rng.next() % 5) as i32 - 2),
                    None => rng.i32(),
                };
                let second = (rng.next() % 86_401) as u32;
                let nano = (rng.next() % u64::from(NANOS_PER_SECOND)) as u32;
                Epoch::<Utc>::from_parts(day, second, nano).unwrap()
            };
            let a = epoch(&mut rng, None);
            let near = rng.next().is_multiple_of(2).then(|| a.day());
            let b = epoch(&mut rng, near);
            check(a, b);
            check(b, a);
        }
    }
}
