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
/// Computed in `i64`; the result saturates at the ends of `i32` (years beyond ±5.8 million).
pub const fn days_from_civil(year: i32, month: u8, day: u8) -> i32 {
    let year = year as i64;
    let y = if month <= 2 { year - 1 } else { year };
    let era = if y >= 0 { y } else { y - 399 } / 400;
    let yoe = y - era * 400;
    let m = month as i64;
    let mp = if m > 2 { m - 3 } else { m + 9 };
    let doy = (153 * mp + 2) / 5 + day as i64 - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    let days = era * 146_097 + doe - 719_468 - 10_957;
    if days > i32::MAX as i64 {
        i32::MAX
    } else if days < i32::MIN as i64 {
        i32::MIN
    } else {
        days as i32
    }
}

/// The Gregorian (year, month, day) of a day count from 2000-01-01 (inverse of [`days_from_civil`]).
///
/// Exact for every `i32` day count: the 400-year era is found in `i64` (so the extreme day
/// counts a saturated [`Epoch::add`] can produce do not overflow), the rest in `i32` (one 64-bit
/// division instead of nine: on the MSP430 these are library calls).
pub const fn civil_from_days(days: i32) -> (i32, u8, u8) {
    let z = days as i64 + 10_957 + 719_468;
    let era = if z >= 0 { z } else { z - 146_096 } / 146_097;
    // 0 ≤ doe ≤ 146 096 and |era| ≤ 14 700: everything below fits i32
    let doe = (z - era * 146_097) as i32;
    let era = era as i32;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let y = yoe + era * 400;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = if m <= 2 { y + 1 } else { y };
    (year, m as u8, d as u8)
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
        if !(Self::MIN_YEAR..=Self::MAX_YEAR).contains(&c.year) {
            return Err(TimeError::Year(c.year));
        }
        if !(1..=12).contains(&c.month) {
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

    /// The span from `earlier` to `self` (negative if `earlier` is later). UTC days count 86 400 s.
    pub fn span_since(&self, earlier: &Self) -> TimeSpan {
        let days = i64::from(self.day) - i64::from(earlier.day);
        let secs =
            days * i64::from(SECONDS_PER_DAY) + i64::from(self.second) - i64::from(earlier.second);
        let nanos = i64::from(self.nano) - i64::from(earlier.nano);
        TimeSpan::from_seconds_nanos_i64(secs, nanos)
    }

    /// This epoch moved by `span` (days count 86 400 s). Saturates at the ends of the day range.
    pub fn add(&self, span: TimeSpan) -> Self {
        let mut nano = i64::from(self.nano) + i64::from(span.nano);
        let mut secs = i64::from(self.second) + i64::from(span.seconds);
        if nano >= i64::from(NANOS_PER_SECOND) {
            nano -= i64::from(NANOS_PER_SECOND);
            secs += 1;
        }
        let spd = i64::from(SECONDS_PER_DAY);
        let day = i64::from(self.day) + secs.div_euclid(spd);
        let second = secs.rem_euclid(spd);
        Self {
            day: day.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32,
            second: second as u32,
            nano: nano as u32,
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
        let year = if yy < 57 {
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
        // 1e-8 day = 864 µs = 864 000 ns exactly.
        let total_ns = u64::from(frac_1e8) * 864_000;
        let second = (total_ns / u64::from(NANOS_PER_SECOND)) as u32;
        let nano = (total_ns % u64::from(NANOS_PER_SECOND)) as u32;
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
            seconds: total_secs.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32,
            nano,
        }
    }

    /// A span of whole seconds and nanoseconds (nanoseconds may be any value; they are carried).
    pub fn new(seconds: i32, nanos: i64) -> Self {
        Self::from_seconds_nanos_i64(i64::from(seconds), nanos)
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
    LEAP_SECONDS.iter().rev().find(|e| e.day <= day).copied()
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
        Ok(self.to_tai()?.to_tt())
    }

    /// As [`Epoch::<Utc>::to_tt`] with [`Epoch::<Utc>::to_tai_extrapolated`].
    ///
    /// # Errors
    /// As [`Epoch::<Utc>::to_tai_extrapolated`].
    pub fn to_tt_extrapolated(&self) -> Result<Epoch<Tt>, TimeError> {
        Ok(self.to_tai_extrapolated()?.to_tt())
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
                let ns = i64::from(d.seconds) * i64::from(NANOS_PER_SECOND) + i64::from(d.nano);
                if ns.abs() > 900_000_000 {
                    let ms = (ns / 1_000_000).clamp(i64::from(i32::MIN), i64::from(i32::MAX));
                    return Err(TimeError::Dut1(ms as i32));
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
            .rposition(|e| start_tai(e) <= *self)
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
        self.add(TimeSpan::new(0, TT_MINUS_TAI_NS)).relabel()
    }
}

impl Epoch<Tt> {
    /// TT → TAI (`TAI = TT − 32.184 s`, exact).
    pub fn to_tai(&self) -> Epoch<Tai> {
        self.add(TimeSpan::new(0, -TT_MINUS_TAI_NS)).relabel()
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
        if !(min_day..=max_day).contains(&day_f) {
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
    pub fn decimal_year_split(&self) -> (i32, f32) {
        let (year, _, _) = civil_from_days(self.day);
        let day_of_year = self.day - days_from_civil(year, 1, 1);
        let days_in_year: f32 = if is_leap_year(year) { 366.0 } else { 365.0 };
        let fraction = (day_of_year as f32 + self.day_fraction_f32()) / days_in_year;
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
const TWO_PI_Q29: u64 = 3_373_259_426;

/// The linear part of GMST (everything but the T² and T³ terms) as a binary angle:
/// `u64` where 2^64 is one revolution, so the reduction modulo 2π is exact wrapping.
fn gmst_linear_bam(ut1: &Epoch<Ut1>) -> u64 {
    let day = i64::from(ut1.day) as u64;
    GMST_DAY0_BAM
        .wrapping_add(GMST_PER_DAY_BAM.wrapping_mul(day))
        .wrapping_add(GMST_PER_SECOND_BAM.wrapping_mul(u64::from(ut1.second)))
        .wrapping_add(GMST_PER_MICRO_BAM.wrapping_mul(u64::from(ut1.nano / 1000)))
        .wrapping_add(GMST_PER_NANO_BAM.wrapping_mul(u64::from(ut1.nano % 1000)))
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
/// 876 600 h·T term is a whole number of revolutions per day and vanishes); the small T² and
/// T³ terms are added in f32. The result is rounded to f32 once.
///
/// Accuracy: measured against an f64 `gstime` over 1990–2050 (200 000 instants), max
/// 2.40e-7 rad (half an f32 ulp near 2π), RMS 9.2e-8 rad
/// (`cargo test --test time gmst -- --nocapture`). The model itself (IAU-82, UT1) is
/// within ~0.1 mas/yr of the Earth rotation angle definitions in use since 2003; using UTC for
/// UT1 costs up to 6.6e-5 rad (see [`Epoch::<Utc>::to_ut1`]).
pub fn gmst_rad(ut1: &Epoch<Ut1>) -> f32 {
    let (whole, fraction) = ut1.days_since_j2000_split();
    let t = (whole + fraction) / 36_525.0;
    // 0.093 104 s·T² − 6.2e-6 s·T³, as revolutions, as a binary angle (|·| < 2e14 for |T| < 1).
    let quadratic_rev = (0.093_104 * t * t - 6.2e-6 * t * t * t) / 86_400.0;
    let quadratic_bam = (quadratic_rev * REV_BAM as f32) as i64;
    let bam = gmst_linear_bam(ut1).wrapping_add_signed(quadratic_bam);
    // Top 32 bits × 2π·2^29 = radians · 2^61, then one rounding to f32.
    let q61 = (bam >> 32) * TWO_PI_Q29;
    q61 as f32 * (1.0 / 2_305_843_009_213_693_952.0)
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
    let bam = gmst_linear_bam(ut1).wrapping_add_signed(quadratic_bam);
    bam as f64 * (core::f64::consts::TAU / REV_BAM)
}
