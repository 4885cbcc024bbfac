//! STK ephemeris files (`.e`, `EphemerisTimePosVel`): reader and writer (host only).
//!
//! The subset of the STK 11 external-ephemeris format that the reference files in
//! `tests/data/sgp4/*.e` use and that `acs propagate` writes (`docs/cli.md`):
//!
//! ```text
//! stk.v.11.0
//! # comment lines start with '#'
//! BEGIN Ephemeris
//! NumberOfEphemerisPoints 10081
//! ScenarioEpoch 15 Jun 2009 04:56:45.472650
//! InterpolationMethod Lagrange
//! InterpolationSamplesM1 5
//! CentralBody Earth
//! CoordinateSystem TEMEOfDate
//! DistanceUnit Meters
//! EphemerisTimePosVel
//! t x y z vx vy vz
//! ...
//! END Ephemeris
//! ```
//!
//! Each row is `t` in seconds from `ScenarioEpoch` (UTC), the position in metres and the
//! velocity in m/s, in `CoordinateSystem`. The reader checks the structure (version line,
//! `BEGIN`/`END`, the declared point count, seven finite numbers per row, strictly increasing
//! times) and reports the 1-based line number with every error ([`StkError`]). Header keywords
//! it does not know are kept in order ([`StkEphemeris::other_keywords`]) and written back.
//! Only `DistanceUnit Meters` (STK's default) and the `EphemerisTimePosVel` data format are
//! supported; anything else is an error, never a silent misreading.
//!
//! The writer prints what the reference files print: `t`, `x y z` with 6 decimals (1 µm) and
//! `vx vy vz` with 9 decimals, the date as `dd Mon yyyy hh:mm:ss.ffffff` (9 decimals when the
//! epoch has sub-microsecond nanoseconds). `write(read(text)) == text` for every reference file,
//! and `read(write(e))` returns `e` with the rows rounded to those decimals (exactly `e` when `e`
//! was itself read from a file). Comments are written after the version line.
//!
//! # Which epoch the rows count from (the reference files' `ScenarioEpoch`)
//! In the reference files `ScenarioEpoch` is **not** the TLE epoch: DTUSAT's TLE epoch is
//! 2009-06-15 04:56:45.714624 UTC (09166.20608466) but the files say 04:56:45.472650, 0.241974 s
//! earlier; the twelve `sat900xx` files differ by −0.23 s to +0.58 s. The offsets equal
//! −(UT1 − UTC) at each TLE epoch (+0.41 s in May 2008, −0.24 s in June 2009 after the 2008 leap
//! second, +0.56 s in May 2012 and +0.58 s in April 2015 just before leap seconds, ≈ 0 in 2013,
//! 2016 and 2023), so the generator took the TLE epoch as UT1 and printed it converted to UTC.
//! The rows, however, are SGP4 at `tsince = t / 60` minutes **from the TLE epoch**:
//! `tests/stk.rs` propagates DTUSAT with the `sgp4` crate and matches the rows at the µm level
//! with the TLE epoch, and misses by about 1.8 km (0.242 s × 7.5 km/s) with the header's epoch.
//! **Tests must therefore take `t` as seconds from the TLE epoch and ignore `ScenarioEpoch`**
//! of the reference files. Files written by `acs propagate` put the TLE epoch (UTC) in
//! `ScenarioEpoch`, as cli.md specifies, so for them the two readings agree.

use std::fmt;
use std::fmt::Write as _;

use crate::time::{Calendar, Epoch, TimeSpan, Utc};

/// The version line written by [`write()`].
pub const VERSION: &str = "stk.v.11.0";

/// The data format keyword this module reads and writes.
const DATA_FORMAT: &str = "EphemerisTimePosVel";

/// Month abbreviations of the STK date format.
const MONTHS: [&str; 12] = [
    "Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec",
];

/// The coordinate system of the rows.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum CoordinateSystem {
    /// `TEMEOfDate`: SGP4's True Equator, Mean Equinox of date.
    TemeOfDate,
    /// `J2000`: mean equator and equinox of J2000.0.
    J2000,
    /// Any other STK name, kept verbatim.
    Other(String),
}

impl CoordinateSystem {
    /// The STK keyword value.
    pub fn as_str(&self) -> &str {
        match self {
            Self::TemeOfDate => "TEMEOfDate",
            Self::J2000 => "J2000",
            Self::Other(s) => s,
        }
    }

    fn from_keyword(s: &str) -> Self {
        match s {
            "TEMEOfDate" => Self::TemeOfDate,
            "J2000" => Self::J2000,
            other => Self::Other(other.to_owned()),
        }
    }
}

/// One ephemeris point.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct StateRow {
    /// Time from the scenario epoch, s.
    pub t_s: f64,
    /// Position, m.
    pub r_m: [f64; 3],
    /// Velocity, m/s.
    pub v_mps: [f64; 3],
}

/// An STK ephemeris file in memory.
#[derive(Clone, Debug, PartialEq)]
pub struct StkEphemeris {
    /// The version line, e.g. `stk.v.11.0`.
    pub version: String,
    /// Comment lines, without the leading `#` and one following blank.
    pub comments: Vec<String>,
    /// `ScenarioEpoch`, UTC: the instant `t_s = 0` of the rows.
    pub scenario_epoch: Epoch<Utc>,
    /// `InterpolationMethod` (e.g. `Lagrange`), if given.
    pub interpolation_method: Option<String>,
    /// `InterpolationSamplesM1` (interpolation order), if given.
    pub interpolation_samples_m1: Option<u32>,
    /// `CentralBody` (`Earth` when absent, STK's default).
    pub central_body: String,
    /// `CoordinateSystem`.
    pub coordinate_system: CoordinateSystem,
    /// Other header keywords and their values, in file order.
    pub other_keywords: Vec<(String, String)>,
    /// The rows, times strictly increasing.
    pub rows: Vec<StateRow>,
}

impl StkEphemeris {
    /// An empty ephemeris with the header `acs propagate` writes: version 11, Lagrange
    /// interpolation with 5 samples minus one (as the reference files), central body Earth.
    pub fn new(scenario_epoch: Epoch<Utc>, coordinate_system: CoordinateSystem) -> Self {
        Self {
            version: VERSION.to_owned(),
            comments: Vec::new(),
            scenario_epoch,
            interpolation_method: Some("Lagrange".to_owned()),
            interpolation_samples_m1: Some(5),
            central_body: "Earth".to_owned(),
            coordinate_system,
            other_keywords: Vec::new(),
            rows: Vec::new(),
        }
    }

    /// The UTC instant of a row: `scenario_epoch + t_s` (UTC days of 86 400 s). See the
    /// module doc on what the reference files' `ScenarioEpoch` means.
    pub fn epoch_of(&self, row: &StateRow) -> Result<Epoch<Utc>, crate::time::TimeError> {
        Ok(self
            .scenario_epoch
            .add(TimeSpan::from_seconds_f64(row.t_s)?))
    }
}

/// What went wrong in an STK file.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum StkErrorKind {
    /// The first non-comment line is not a `stk.v.*` version line.
    NotStkFile {
        /// The line found.
        found: String,
    },
    /// `BEGIN Ephemeris` was expected.
    ExpectedBegin {
        /// The line found.
        found: String,
    },
    /// A header keyword appears twice.
    DuplicateKeyword {
        /// The keyword.
        keyword: String,
    },
    /// A header keyword has a value that cannot be read.
    BadValue {
        /// The keyword.
        keyword: String,
        /// Its value.
        value: String,
    },
    /// A header value or data format this reader does not support.
    Unsupported {
        /// The keyword.
        keyword: String,
        /// Its value.
        value: String,
    },
    /// A required keyword is missing (reported at the line of the data format keyword).
    MissingKeyword {
        /// The keyword.
        keyword: &'static str,
    },
    /// A data row does not have seven fields.
    FieldCount {
        /// The number of fields found.
        found: usize,
    },
    /// A data row field is not a finite number.
    BadNumber {
        /// Its 1-based position in the row (1 = t, 2..4 = position, 5..7 = velocity).
        field: usize,
        /// The text.
        text: String,
    },
    /// Times do not increase strictly.
    TimeNotIncreasing {
        /// The previous row's time, s.
        previous_s: f64,
        /// This row's time, s.
        t_s: f64,
    },
    /// `NumberOfEphemerisPoints` differs from the number of rows (reported at `END`).
    PointCount {
        /// The declared count.
        declared: usize,
        /// The rows read.
        found: usize,
    },
    /// The file ends before `END Ephemeris` (reported at the last line).
    MissingEnd,
    /// Text after `END Ephemeris`.
    TrailingText {
        /// The line found.
        found: String,
    },
}

/// An error reading an STK file: the 1-based line number and what is wrong there.
#[derive(Clone, Debug, PartialEq)]
pub struct StkError {
    /// 1-based line number.
    pub line: usize,
    /// What is wrong.
    pub kind: StkErrorKind,
}

impl fmt::Display for StkErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotStkFile { found } => write!(f, "not an STK file: {found:?}"),
            Self::ExpectedBegin { found } => {
                write!(f, "expected \"BEGIN Ephemeris\", found {found:?}")
            }
            Self::DuplicateKeyword { keyword } => write!(f, "keyword {keyword} given twice"),
            Self::BadValue { keyword, value } => write!(f, "bad value {value:?} for {keyword}"),
            Self::Unsupported { keyword, value } => {
                write!(f, "unsupported {keyword} {value:?}")
            }
            Self::MissingKeyword { keyword } => write!(f, "keyword {keyword} missing"),
            Self::FieldCount { found } => {
                write!(f, "expected 7 numbers (t x y z vx vy vz), found {found}")
            }
            Self::BadNumber { field, text } => {
                write!(f, "field {field} {text:?} is not a finite number")
            }
            Self::TimeNotIncreasing { previous_s, t_s } => {
                write!(f, "time {t_s} s does not follow {previous_s} s")
            }
            Self::PointCount { declared, found } => write!(
                f,
                "NumberOfEphemerisPoints says {declared}, the file has {found} rows"
            ),
            Self::MissingEnd => f.write_str("\"END Ephemeris\" missing"),
            Self::TrailingText { found } => {
                write!(f, "unexpected text after END Ephemeris: {found:?}")
            }
        }
    }
}

impl fmt::Display for StkError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "STK ephemeris line {}: {}", self.line, self.kind)
    }
}

impl std::error::Error for StkError {}

/// Parses an STK date, `dd Mon yyyy hh:mm:ss[.fffffffff]` (e.g. `15 Jun 2009 04:56:45.472650`),
/// as a UTC epoch. `None` if it is malformed or out of range (second 60 is accepted).
pub fn parse_date(text: &str) -> Option<Epoch<Utc>> {
    let mut parts = text.split_whitespace();
    let (day, month, year, time) = (parts.next()?, parts.next()?, parts.next()?, parts.next()?);
    if parts.next().is_some() {
        return None;
    }
    let day: u8 = digits(day, 1, 2)?.try_into().ok()?;
    let month = MONTHS.iter().position(|m| m.eq_ignore_ascii_case(month))?;
    let year: i32 = digits(year, 4, 4)?.try_into().ok()?;
    let mut hms = time.split(':');
    let (h, m, s) = (hms.next()?, hms.next()?, hms.next()?);
    if hms.next().is_some() {
        return None;
    }
    // seconds with up to 9 decimals, read exactly (no float)
    let (whole, nano) = match s.split_once('.') {
        Some((w, f)) => (w, digits(f, 1, 9)? * 10_u32.pow(9 - f.len() as u32)),
        None => (s, 0),
    };
    let calendar = Calendar {
        year,
        month: u8::try_from(month + 1).ok()?,
        day,
        hour: digits(h, 2, 2)?.try_into().ok()?,
        minute: digits(m, 2, 2)?.try_into().ok()?,
        second: digits(whole, 2, 2)?.try_into().ok()?,
        nano,
    };
    Epoch::from_calendar(calendar).ok()
}

/// A decimal integer of `min..=max` ASCII digits.
fn digits(s: &str, min: usize, max: usize) -> Option<u32> {
    if s.len() < min || s.len() > max || !s.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    s.parse().ok()
}

/// Formats a UTC epoch as an STK date, `dd Mon yyyy hh:mm:ss.ffffff` (9 decimals if the
/// nanoseconds are not whole microseconds), the inverse of [`parse_date`].
pub fn format_date(epoch: &Epoch<Utc>) -> String {
    let c = epoch.to_calendar();
    let month = MONTHS
        .get(usize::from(c.month).wrapping_sub(1))
        .copied()
        .unwrap_or("???");
    let fraction = if c.nano.is_multiple_of(1000) {
        format!("{:06}", c.nano / 1000)
    } else {
        format!("{:09}", c.nano)
    };
    format!(
        "{:02} {month} {:04} {:02}:{:02}:{:02}.{fraction}",
        c.day, c.year, c.hour, c.minute, c.second
    )
}

/// Where the reader is in the file.
enum Section {
    Version,
    Begin,
    Header,
    Data,
    End,
}

/// Reads an STK ephemeris file (see the module doc for what is accepted).
pub fn read(text: &str) -> Result<StkEphemeris, StkError> {
    let mut section = Section::Version;
    let mut version = String::new();
    let mut comments = Vec::new();
    let mut keywords: Vec<(String, String, usize)> = Vec::new();
    let mut rows: Vec<StateRow> = Vec::new();
    let mut header_end_line = 0;
    let mut last_line = 0;
    let mut end_line = 0;

    for (index, raw) in text.lines().enumerate() {
        let line_no = index + 1;
        last_line = line_no;
        let line = raw.trim();
        let err = |kind| StkError {
            line: line_no,
            kind,
        };
        if line.is_empty() {
            continue;
        }
        if let Some(comment) = line.strip_prefix('#') {
            if !matches!(section, Section::Data) {
                comments.push(comment.strip_prefix(' ').unwrap_or(comment).to_owned());
            }
            continue;
        }
        match section {
            Section::Version => {
                if !line.starts_with("stk.v.") {
                    return Err(err(StkErrorKind::NotStkFile {
                        found: line.to_owned(),
                    }));
                }
                version = line.to_owned();
                section = Section::Begin;
            }
            Section::Begin => {
                if !is_keyword_line(line, "BEGIN", "Ephemeris") {
                    return Err(err(StkErrorKind::ExpectedBegin {
                        found: line.to_owned(),
                    }));
                }
                section = Section::Header;
            }
            Section::Header => {
                let (keyword, value) = match line.split_once(char::is_whitespace) {
                    Some((k, v)) => (k, v.trim()),
                    None => (line, ""),
                };
                if keyword == DATA_FORMAT {
                    header_end_line = line_no;
                    section = Section::Data;
                } else if keyword.starts_with("Ephemeris") || keyword == "END" {
                    return Err(err(StkErrorKind::Unsupported {
                        keyword: "data format".to_owned(),
                        value: line.to_owned(),
                    }));
                } else if keywords.iter().any(|(k, _, _)| k == keyword) {
                    return Err(err(StkErrorKind::DuplicateKeyword {
                        keyword: keyword.to_owned(),
                    }));
                } else {
                    keywords.push((keyword.to_owned(), value.to_owned(), line_no));
                }
            }
            Section::Data => {
                if is_keyword_line(line, "END", "Ephemeris") {
                    end_line = line_no;
                    section = Section::End;
                    continue;
                }
                let row = parse_row(line).map_err(err)?;
                if let Some(previous) = rows.last() {
                    if row.t_s <= previous.t_s {
                        return Err(err(StkErrorKind::TimeNotIncreasing {
                            previous_s: previous.t_s,
                            t_s: row.t_s,
                        }));
                    }
                }
                rows.push(row);
            }
            Section::End => {
                return Err(err(StkErrorKind::TrailingText {
                    found: line.to_owned(),
                }))
            }
        }
    }
    match section {
        Section::End => {}
        Section::Version => {
            return Err(StkError {
                line: last_line.max(1),
                kind: StkErrorKind::NotStkFile {
                    found: String::new(),
                },
            })
        }
        _ => {
            return Err(StkError {
                line: last_line.max(1),
                kind: StkErrorKind::MissingEnd,
            })
        }
    }
    build(version, comments, keywords, rows, header_end_line, end_line)
}

/// True if `line` is the two words `first second` (any blanks between).
fn is_keyword_line(line: &str, first: &str, second: &str) -> bool {
    let mut words = line.split_whitespace();
    words.next() == Some(first) && words.next() == Some(second) && words.next().is_none()
}

fn parse_row(line: &str) -> Result<StateRow, StkErrorKind> {
    let mut values = [0.0_f64; 7];
    let mut count = 0;
    for (i, word) in line.split_whitespace().enumerate() {
        count += 1;
        if let Some(slot) = values.get_mut(i) {
            *slot = word
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| StkErrorKind::BadNumber {
                    field: i + 1,
                    text: word.to_owned(),
                })?;
        }
    }
    if count != 7 {
        return Err(StkErrorKind::FieldCount { found: count });
    }
    let [t_s, x, y, z, vx, vy, vz] = values;
    Ok(StateRow {
        t_s,
        r_m: [x, y, z],
        v_mps: [vx, vy, vz],
    })
}

/// Interprets the header keywords once the whole file is read.
fn build(
    version: String,
    comments: Vec<String>,
    keywords: Vec<(String, String, usize)>,
    rows: Vec<StateRow>,
    header_end_line: usize,
    end_line: usize,
) -> Result<StkEphemeris, StkError> {
    let mut scenario_epoch = None;
    let mut interpolation_method = None;
    let mut interpolation_samples_m1 = None;
    let mut central_body = None;
    let mut coordinate_system = None;
    let mut declared_points = None;
    let mut other_keywords = Vec::new();
    for (keyword, value, line) in keywords {
        let bad = |keyword: String, value: String| StkError {
            line,
            kind: StkErrorKind::BadValue { keyword, value },
        };
        match keyword.as_str() {
            "ScenarioEpoch" => {
                scenario_epoch = Some(parse_date(&value).ok_or_else(|| bad(keyword, value))?);
            }
            "NumberOfEphemerisPoints" => {
                declared_points = Some(value.parse::<usize>().map_err(|_| bad(keyword, value))?);
            }
            "InterpolationMethod" => interpolation_method = Some(value),
            "InterpolationSamplesM1" => {
                interpolation_samples_m1 =
                    Some(value.parse::<u32>().map_err(|_| bad(keyword, value))?);
            }
            "CentralBody" => central_body = Some(value),
            "CoordinateSystem" => coordinate_system = Some(CoordinateSystem::from_keyword(&value)),
            "DistanceUnit" => {
                if value != "Meters" {
                    return Err(StkError {
                        line,
                        kind: StkErrorKind::Unsupported { keyword, value },
                    });
                }
            }
            _ => other_keywords.push((keyword, value)),
        }
    }
    let missing = |keyword| StkError {
        line: header_end_line,
        kind: StkErrorKind::MissingKeyword { keyword },
    };
    let scenario_epoch = scenario_epoch.ok_or_else(|| missing("ScenarioEpoch"))?;
    let coordinate_system = coordinate_system.ok_or_else(|| missing("CoordinateSystem"))?;
    if let Some(declared) = declared_points {
        if declared != rows.len() {
            return Err(StkError {
                line: end_line,
                kind: StkErrorKind::PointCount {
                    declared,
                    found: rows.len(),
                },
            });
        }
    }
    Ok(StkEphemeris {
        version,
        comments,
        scenario_epoch,
        interpolation_method,
        interpolation_samples_m1,
        central_body: central_body.unwrap_or_else(|| "Earth".to_owned()),
        coordinate_system,
        other_keywords,
        rows,
    })
}

/// Writes an STK ephemeris file (see the module doc for the number formats). The rows are
/// written as given; a file whose times do not increase strictly will not read back.
pub fn write(e: &StkEphemeris) -> String {
    let mut out = String::with_capacity(200 + e.rows.len() * 110);
    // `write!` to a String cannot fail.
    let _ = writeln!(out, "{}", e.version);
    for c in &e.comments {
        let _ = writeln!(out, "# {c}");
    }
    out.push_str("BEGIN Ephemeris\n");
    let _ = writeln!(out, "NumberOfEphemerisPoints {}", e.rows.len());
    let _ = writeln!(out, "ScenarioEpoch {}", format_date(&e.scenario_epoch));
    if let Some(m) = &e.interpolation_method {
        let _ = writeln!(out, "InterpolationMethod {m}");
    }
    if let Some(n) = e.interpolation_samples_m1 {
        let _ = writeln!(out, "InterpolationSamplesM1 {n}");
    }
    let _ = writeln!(out, "CentralBody {}", e.central_body);
    let _ = writeln!(out, "CoordinateSystem {}", e.coordinate_system.as_str());
    out.push_str("DistanceUnit Meters\n");
    for (k, v) in &e.other_keywords {
        let _ = writeln!(out, "{k} {v}");
    }
    let _ = writeln!(out, "{DATA_FORMAT}");
    for row in &e.rows {
        write_row(&mut out, row);
    }
    out.push_str("END Ephemeris\n");
    out
}

/// Appends one row: `t x y z` with 6 decimals, `vx vy vz` with 9.
pub fn write_row(out: &mut String, row: &StateRow) {
    let [x, y, z] = row.r_m;
    let [vx, vy, vz] = row.v_mps;
    let _ = writeln!(
        out,
        "{:.6} {x:.6} {y:.6} {z:.6} {vx:.9} {vy:.9} {vz:.9}",
        row.t_s
    );
}
