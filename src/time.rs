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
//! which the UTC epoch represents as second 86 400 of the day (see [`leap_seconds`]). Within UTC,
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
        #[derive(Copy, Clone, Debug, PartialEq, Eq, Default)]
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
pub const fn days_from_civil(year: i32, month: u8, day: u8) -> i32 {
    let y = if month <= 2 { year - 1 } else { year };
    let era = if y >= 0 { y } else { y - 399 } / 400;
    let yoe = y - era * 400;
    let m = month as i32;
    let mp = if m > 2 { m - 3 } else { m + 9 };
    let doy = (153 * mp + 2) / 5 + day as i32 - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 719_468 - 10_957
}

/// The Gregorian (year, month, day) of a day count from 2000-01-01 (inverse of [`days_from_civil`]).
pub const fn civil_from_days(days: i32) -> (i32, u8, u8) {
    let z = days + 10_957 + 719_468;
    let era = if z >= 0 { z } else { z - 146_096 } / 146_097;
    let doe = z - era * 146_097;
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
