//! Two-line element sets: a column-exact parser with checksum verification (notes 000 §3.3,
//! 003 §2.1; the format of Spacetrack Report #3 and Vallado et al. 2006 `twoline2rv`).
//!
//! `no_std`, no allocation. Every malformed input gives a [`TleError`] naming the line (0 = the
//! name line, 1, 2), the 1-based column and the [`TleField`], with a [`TleErrorKind`] that carries
//! the offending character or value.
//!
//! # The format (1-based columns, inclusive)
//! | line 1 | field | line 2 | field |
//! |---|---|---|---|
//! | 1 | line number `1` | 1 | line number `2` |
//! | 3–7 | catalogue number (Alpha-5 allowed) | 3–7 | catalogue number (same as line 1) |
//! | 8 | classification `U`, `C` or `S` | 9–16 | inclination, deg |
//! | 10–17 | international designator (may be blank) | 18–25 | RAAN Ω, deg |
//! | 19–20 | epoch year, two digits (< 57 → 20yy) | 27–33 | eccentricity, implied `0.` |
//! | 21–32 | epoch day of year `DDD.DDDDDDDD` | 35–42 | argument of perigee ω, deg |
//! | 34–43 | ṅ/2, rev/day² | 44–51 | mean anomaly M, deg |
//! | 45–52 | n̈/6, rev/day³, `±NNNNN±E` (blank = 0) | 53–63 | mean motion n, rev/day |
//! | 54–61 | B*, 1/earth radii, `±NNNNN±E` | 64–68 | revolution number at epoch |
//! | 63 | ephemeris type (blank = 0) | 69 | checksum |
//! | 65–68 | element set number | | |
//! | 69 | checksum | | |
//!
//! All other columns up to 69 are separators and must be blank: a TLE whose spaces were
//! collapsed (as in the thesis's printed copy, note 000 §3.3) is rejected at the first shifted
//! column instead of being read wrongly. Characters after column 69 are ignored (the
//! verification file `SGP4-VER.TLE` appends start, stop and step there), as is a trailing `\r`.
//!
//! **Checksum**: the sum of the digits in columns 1–68, each `-` counting 1, modulo 10, equals
//! column 69 ([`checksum`]).
//!
//! **Numbers are exact.** Each decimal field is read as an integer mantissa and a power of ten
//! and converted with one correctly rounded division, so the f64 is the one nearest to the
//! printed decimal (the same value as Rust's `str::parse::<f64>`). The exponent fields
//! `" 31026-4"` mean `+0.31026e-4`. The epoch's day fraction is read as an integer count of
//! 1e-8 day and converted exactly to nanoseconds by [`Epoch::from_tle_epoch`] (no float).
//!
//! **Leniency, exactly**: right-justified numbers may have leading blanks (`" 98.7036"`,
//! `"   13"`); the international designator, n̈/6 and the ephemeris type may be blank; the
//! name line may start with `"0 "`. Nothing else is guessed.
//!
//! [`Tle::validate`] checks the value ranges (eccentricity in 0..1, mean motion > 0, angles in
//! their circle); [`Tle::parse`] calls it, and it can be called on a hand-built [`Tle`].

use core::fmt;

use crate::time::{Epoch, Utc};

/// The length of a TLE data line: columns 1–69 (anything after column 69 is ignored).
pub const LINE_LENGTH: usize = 69;
/// The longest name line (line 0) kept, in characters.
pub const NAME_LENGTH: usize = 24;

/// A parsed element set, with the values exactly as the TLE states them (mean elements in the
/// TEME frame of the epoch, Kozai mean motion as the format defines).
///
/// The angle and mean-motion fields are f64: the parse is a one-time operation and the eighth
/// decimal of the mean motion matters (a relative error of 6e-8, f32's, is 120 m after 3 days).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Tle {
    /// The optional name line ("line 0"), trimmed, at most 24 characters.
    pub name: Option<heapless::String<24>>,
    /// NORAD catalogue number (line 1 columns 3–7; Alpha-5 letters are accepted: `A0000` =
    /// 100 000, letters I and O skipped, up to `Z9999` = 339 999).
    pub catalog_number: u32,
    /// Classification (line 1 column 8): `U`, `C` or `S`.
    pub classification: u8,
    /// International designator (line 1 columns 10–17), trimmed (empty when blank).
    pub international_designator: heapless::String<8>,
    /// Epoch (line 1 columns 19–32), UTC.
    pub epoch: Epoch<Utc>,
    /// First derivative of the mean motion divided by two (line 1 columns 34–43), rev/day².
    pub mean_motion_dot: f64,
    /// Second derivative of the mean motion divided by six (line 1 columns 45–52), rev/day³.
    pub mean_motion_ddot: f64,
    /// B* drag term (line 1 columns 54–61), 1/earth radii.
    pub bstar: f64,
    /// Ephemeris type (line 1 column 63), 0 when blank.
    pub ephemeris_type: u8,
    /// Element set number (line 1 columns 65–68).
    pub element_set_number: u16,
    /// Inclination (line 2 columns 9–16), degrees.
    pub inclination_deg: f64,
    /// Right ascension of the ascending node (line 2 columns 18–25), degrees.
    pub raan_deg: f64,
    /// Eccentricity (line 2 columns 27–33, implied leading decimal point), 0..1.
    pub eccentricity: f64,
    /// Argument of perigee (line 2 columns 35–42), degrees.
    pub arg_perigee_deg: f64,
    /// Mean anomaly (line 2 columns 44–51), degrees.
    pub mean_anomaly_deg: f64,
    /// Mean motion (line 2 columns 53–63), revolutions per day.
    pub mean_motion_rev_per_day: f64,
    /// Revolution number at epoch (line 2 columns 64–68).
    pub revolution_number: u32,
}

/// Whether [`Tle::parse_with`] verifies the checksums (column 69).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Checksum {
    /// Verify both lines (the default of [`Tle::parse`]).
    Verify,
    /// Do not read column 69 at all. Only for hand-edited test sets such as the error-code cases
    /// at the end of `SGP4-VER.TLE`, whose checksums were not updated.
    Ignore,
}

/// A field (or column group) of a TLE, as named in errors.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum TleField {
    /// The whole line (a missing or extra line).
    Line,
    /// The name line (line 0).
    Name,
    /// Column 1: the line number.
    LineNumber,
    /// A column that must be blank between two fields.
    Separator,
    /// Columns 3–7: the catalogue number.
    CatalogNumber,
    /// Line 1 column 8.
    Classification,
    /// Line 1 columns 10–17.
    InternationalDesignator,
    /// Line 1 columns 19–20.
    EpochYear,
    /// Line 1 columns 21–32.
    EpochDay,
    /// Line 1 columns 34–43: ṅ/2.
    MeanMotionDot,
    /// Line 1 columns 45–52: n̈/6.
    MeanMotionDdot,
    /// Line 1 columns 54–61: B*.
    Bstar,
    /// Line 1 column 63.
    EphemerisType,
    /// Line 1 columns 65–68.
    ElementSetNumber,
    /// Line 2 columns 9–16.
    Inclination,
    /// Line 2 columns 18–25.
    Raan,
    /// Line 2 columns 27–33.
    Eccentricity,
    /// Line 2 columns 35–42.
    ArgPerigee,
    /// Line 2 columns 44–51.
    MeanAnomaly,
    /// Line 2 columns 53–63.
    MeanMotion,
    /// Line 2 columns 64–68.
    RevolutionNumber,
    /// Column 69.
    Checksum,
}

impl TleField {
    /// A short English name of the field, for messages.
    pub const fn description(self) -> &'static str {
        match self {
            Self::Line => "line",
            Self::Name => "name",
            Self::LineNumber => "line number",
            Self::Separator => "separator (must be blank)",
            Self::CatalogNumber => "catalogue number",
            Self::Classification => "classification",
            Self::InternationalDesignator => "international designator",
            Self::EpochYear => "epoch year",
            Self::EpochDay => "epoch day of year",
            Self::MeanMotionDot => "mean motion derivative / 2",
            Self::MeanMotionDdot => "mean motion second derivative / 6",
            Self::Bstar => "B* drag term",
            Self::EphemerisType => "ephemeris type",
            Self::ElementSetNumber => "element set number",
            Self::Inclination => "inclination",
            Self::Raan => "right ascension of the ascending node",
            Self::Eccentricity => "eccentricity",
            Self::ArgPerigee => "argument of perigee",
            Self::MeanAnomaly => "mean anomaly",
            Self::MeanMotion => "mean motion",
            Self::RevolutionNumber => "revolution number",
            Self::Checksum => "checksum",
        }
    }

    /// The field that holds a 1-based column of data line 1 or 2 (`Line` for other lines or
    /// columns beyond 69).
    pub const fn at(line: u8, column: u8) -> Self {
        match (line, column) {
            (0, _) => Self::Name,
            (1 | 2, 1) => Self::LineNumber,
            (1 | 2, 3..=7) => Self::CatalogNumber,
            (1 | 2, 69) => Self::Checksum,
            (1, 8) => Self::Classification,
            (1, 10..=17) => Self::InternationalDesignator,
            (1, 19..=20) => Self::EpochYear,
            (1, 21..=32) => Self::EpochDay,
            (1, 34..=43) => Self::MeanMotionDot,
            (1, 45..=52) => Self::MeanMotionDdot,
            (1, 54..=61) => Self::Bstar,
            (1, 63) => Self::EphemerisType,
            (1, 65..=68) => Self::ElementSetNumber,
            (1, 2 | 9 | 18 | 33 | 44 | 53 | 62 | 64) => Self::Separator,
            (2, 9..=16) => Self::Inclination,
            (2, 18..=25) => Self::Raan,
            (2, 27..=33) => Self::Eccentricity,
            (2, 35..=42) => Self::ArgPerigee,
            (2, 44..=51) => Self::MeanAnomaly,
            (2, 53..=63) => Self::MeanMotion,
            (2, 64..=68) => Self::RevolutionNumber,
            (2, 2 | 8 | 17 | 26 | 34 | 43 | 52) => Self::Separator,
            _ => Self::Line,
        }
    }
}

impl fmt::Display for TleField {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.description())
    }
}

/// What is wrong at the place a [`TleError`] names.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum TleErrorKind {
    /// The line has fewer than 69 characters (after removing a trailing `\r`); the column is
    /// the first one missing.
    TooShort {
        /// The line's length in characters.
        length: usize,
    },
    /// A byte that is not ASCII (the column is the first such byte).
    NonAscii,
    /// Column 1 does not hold the line's number (`1` or `2`).
    LineNumber {
        /// The character found.
        found: u8,
    },
    /// The checksum in column 69 disagrees with the one computed from columns 1–68.
    Checksum {
        /// The checksum computed from columns 1–68.
        expected: u8,
        /// The digit in column 69.
        found: u8,
    },
    /// A character other than a digit where the format wants a digit.
    NotDigit {
        /// The character found.
        found: u8,
    },
    /// A separator column that is not blank (often: the columns are shifted).
    NotBlank {
        /// The character found.
        found: u8,
    },
    /// A character the field does not allow (classification not `U`/`C`/`S`, a missing
    /// decimal point, an exponent sign other than `+`/`-`, Alpha-5 letters I and O).
    InvalidCharacter {
        /// The character found.
        found: u8,
    },
    /// The field is blank but the format requires a value.
    Blank,
    /// Lines 1 and 2 name different satellites.
    SatelliteMismatch {
        /// Catalogue number on line 1.
        line1: u32,
        /// Catalogue number on line 2.
        line2: u32,
    },
    /// Eccentricity not in 0 ≤ e < 1 (or not finite).
    Eccentricity {
        /// The value.
        value: f64,
    },
    /// Mean motion not positive (or not finite), rev/day.
    MeanMotionNotPositive {
        /// The value.
        value: f64,
    },
    /// A value outside its range: day of year outside the year, inclination outside 0..=180°,
    /// another angle outside 0..=360°, a non-finite value in a hand-built [`Tle`], an integer
    /// too large for its type.
    OutOfRange {
        /// The value.
        value: f64,
    },
    /// The name line is longer than [`NAME_LENGTH`] characters after trimming.
    NameTooLong {
        /// Its length in characters.
        length: usize,
    },
    /// [`Tle::parse_text`]: fewer non-blank, non-comment lines than an element set needs.
    MissingLine,
    /// [`Tle::parse_text`]: more than three non-blank, non-comment lines.
    ExtraLine {
        /// The 1-based line number in the text.
        text_line: usize,
    },
}

/// A malformed TLE: where (line, column, field) and what ([`TleErrorKind`]).
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TleError {
    /// The TLE line: 0 for the name line, 1 or 2 for the data lines.
    pub line: u8,
    /// The 1-based column (character position) in that line.
    pub column: u8,
    /// The field that holds the column.
    pub field: TleField,
    /// What is wrong.
    pub kind: TleErrorKind,
}

impl TleError {
    /// An error at `line`, `column`, in the field that holds that column.
    pub const fn at(line: u8, column: u8, kind: TleErrorKind) -> Self {
        Self {
            line,
            column,
            field: TleField::at(line, column),
            kind,
        }
    }
}

/// Writes a byte as a readable character (`'x'`, or its code if not printable).
struct Byte(u8);

impl fmt::Display for Byte {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.is_ascii_graphic() || self.0 == b' ' {
            write!(f, "'{}'", char::from(self.0))
        } else {
            write!(f, "byte 0x{:02x}", self.0)
        }
    }
}

impl fmt::Display for TleErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::TooShort { length } => {
                write!(f, "line too short: {length} characters, need {LINE_LENGTH}")
            }
            Self::NonAscii => f.write_str("non-ASCII character"),
            Self::LineNumber { found } => write!(f, "wrong line number {}", Byte(found)),
            Self::Checksum { expected, found } => {
                write!(f, "bad checksum: computed {expected}, found {found}")
            }
            Self::NotDigit { found } => write!(f, "expected a digit, found {}", Byte(found)),
            Self::NotBlank { found } => {
                write!(
                    f,
                    "expected a blank, found {} (shifted columns?)",
                    Byte(found)
                )
            }
            Self::InvalidCharacter { found } => write!(f, "invalid character {}", Byte(found)),
            Self::Blank => f.write_str("blank, but a value is required"),
            Self::SatelliteMismatch { line1, line2 } => {
                write!(f, "catalogue number {line2} differs from line 1's {line1}")
            }
            Self::Eccentricity { value } => write!(f, "eccentricity {value} not in 0..1"),
            Self::MeanMotionNotPositive { value } => {
                write!(f, "mean motion {value} rev/day not positive")
            }
            Self::OutOfRange { value } => write!(f, "value {value} out of range"),
            Self::NameTooLong { length } => {
                write!(f, "name of {length} characters, at most {NAME_LENGTH}")
            }
            Self::MissingLine => f.write_str("line missing"),
            Self::ExtraLine { text_line } => write!(
                f,
                "unexpected line {text_line}: one element set is at most three lines"
            ),
        }
    }
}

impl fmt::Display for TleError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "TLE line {}, column {} ({}): {}",
            self.line, self.column, self.field, self.kind
        )
    }
}

#[cfg(feature = "std")]
impl std::error::Error for TleError {}

/// The checksum of a TLE data line: the sum of the digits in columns 1–68, each `-` counting
/// 1, modulo 10. Columns beyond the line's end count 0.
pub fn checksum(line: &[u8]) -> u8 {
    let sum: u32 = line
        .iter()
        .take(LINE_LENGTH - 1)
        .map(|&c| match c {
            b'0'..=b'9' => u32::from(c - b'0'),
            b'-' => 1,
            _ => 0,
        })
        .sum();
    (sum % 10) as u8
}

/// Powers of ten exactly representable in f64.
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// `mantissa · 10^exponent`, correctly rounded (one exact operand each side of one rounding),
/// for |exponent| ≤ 22 and mantissa < 2^53, which every TLE field satisfies.
fn scaled(mantissa: u64, exponent: i32) -> f64 {
    let m = mantissa as f64;
    let p = POW10
        .get(exponent.unsigned_abs() as usize)
        .copied()
        .unwrap_or(f64::INFINITY);
    if exponent >= 0 {
        m * p
    } else {
        m / p
    }
}

/// One data line (1 or 2), already checked to be ASCII and at least 69 characters long.
struct DataLine<'a> {
    text: &'a [u8],
    line: u8,
}

impl<'a> DataLine<'a> {
    /// Checks length and ASCII, and removes a trailing `\r` (or `\n`).
    fn new(raw: &'a str, line: u8) -> Result<Self, TleError> {
        let text = raw.trim_end_matches(['\r', '\n']).as_bytes();
        if let Some(i) = text.iter().take(LINE_LENGTH).position(|b| !b.is_ascii()) {
            return Err(TleError::at(line, column(i), TleErrorKind::NonAscii));
        }
        if LINE_LENGTH > text.len() {
            return Err(TleError::at(
                line,
                column(text.len()),
                TleErrorKind::TooShort { length: text.len() },
            ));
        }
        let text = text.get(..LINE_LENGTH).unwrap_or(text);
        let this = Self { text, line };
        let expected = b'0' + line;
        match this.byte(1) {
            c if c == expected => Ok(this),
            found => Err(this.err(1, TleErrorKind::LineNumber { found })),
        }
    }

    fn err(&self, column: u8, kind: TleErrorKind) -> TleError {
        TleError::at(self.line, column, kind)
    }

    /// The character at a 1-based column (blank beyond the end, which cannot happen after
    /// [`DataLine::new`]).
    fn byte(&self, column: u8) -> u8 {
        self.text
            .get(usize::from(column).wrapping_sub(1))
            .copied()
            .unwrap_or(b' ')
    }

    /// Columns `first..=last` as (column, character) pairs.
    fn columns(&self, first: u8, last: u8) -> impl Iterator<Item = (u8, u8)> + '_ {
        (first..=last).map(move |c| (c, self.byte(c)))
    }

    fn is_blank(&self, first: u8, last: u8) -> bool {
        self.columns(first, last).all(|(_, c)| c == b' ')
    }

    /// Checks that the separator columns are blank.
    fn separators(&self, columns: &[u8]) -> Result<(), TleError> {
        for &c in columns {
            let found = self.byte(c);
            if found != b' ' {
                return Err(self.err(c, TleErrorKind::NotBlank { found }));
            }
        }
        Ok(())
    }

    /// Verifies column 69 against columns 1–68.
    fn verify_checksum(&self) -> Result<(), TleError> {
        let found = self.byte(69);
        if !found.is_ascii_digit() {
            return Err(self.err(69, TleErrorKind::NotDigit { found }));
        }
        let expected = checksum(self.text);
        let found = found - b'0';
        if expected == found {
            Ok(())
        } else {
            Err(self.err(69, TleErrorKind::Checksum { expected, found }))
        }
    }

    /// A right-justified unsigned integer: leading blanks, then at least one digit, digits only.
    /// `None` when the whole field is blank.
    fn uint_or_blank(&self, first: u8, last: u8) -> Result<Option<u32>, TleError> {
        let mut value: Option<u32> = None;
        for (col, c) in self.columns(first, last) {
            match (c, value) {
                (b' ', None) => {}
                (b'0'..=b'9', v) => {
                    let digit = u32::from(c - b'0');
                    // at most 5 digits: no overflow
                    value = Some(v.unwrap_or(0) * 10 + digit);
                }
                (found, _) => return Err(self.err(col, TleErrorKind::NotDigit { found })),
            }
        }
        Ok(value)
    }

    /// As [`DataLine::uint_or_blank`], with a blank field an error.
    fn uint(&self, first: u8, last: u8) -> Result<u32, TleError> {
        self.uint_or_blank(first, last)?
            .ok_or_else(|| self.err(first, TleErrorKind::Blank))
    }

    /// A right-justified decimal number `[blanks][sign]digits[.digits]` (either digit group may
    /// be empty, not both); the sign only when `signed`. Correctly rounded.
    fn decimal(&self, first: u8, last: u8, signed: bool) -> Result<f64, TleError> {
        if self.is_blank(first, last) {
            return Err(self.err(first, TleErrorKind::Blank));
        }
        let mut negative = false;
        let mut started = false;
        let mut point = false;
        let mut digits = 0_u32;
        let mut fraction_digits = 0_i32;
        let mut mantissa = 0_u64;
        for (col, c) in self.columns(first, last) {
            match c {
                b' ' if !started => {}
                b'+' | b'-' if signed && !started => {
                    negative = c == b'-';
                    started = true;
                }
                b'.' if !point => {
                    point = true;
                    started = true;
                }
                b'0'..=b'9' => {
                    started = true;
                    digits += 1;
                    mantissa = mantissa * 10 + u64::from(c - b'0');
                    if point {
                        fraction_digits += 1;
                    }
                }
                found => return Err(self.err(col, TleErrorKind::NotDigit { found })),
            }
        }
        if digits == 0 {
            // only a sign and/or a point: the digit is missing after them
            let found = self.byte(last);
            return Err(self.err(last, TleErrorKind::NotDigit { found }));
        }
        let magnitude = scaled(mantissa, -fraction_digits);
        Ok(if negative { -magnitude } else { magnitude })
    }

    /// An exponent field of 8 columns from `first`: sign (blank, `+`, `-`), five mantissa digits
    /// with an implied leading `0.`, exponent sign (`+`, `-`), one exponent digit.
    /// `" 31026-4"` = +0.31026e-4. `None` when the whole field is blank.
    fn exponent_field(&self, first: u8) -> Result<Option<f64>, TleError> {
        let last = first + 7;
        if self.is_blank(first, last) {
            return Ok(None);
        }
        let negative = match self.byte(first) {
            b' ' | b'+' => false,
            b'-' => true,
            found => return Err(self.err(first, TleErrorKind::NotDigit { found })),
        };
        let mut mantissa = 0_u64;
        for (col, c) in self.columns(first + 1, first + 5) {
            if !c.is_ascii_digit() {
                return Err(self.err(col, TleErrorKind::NotDigit { found: c }));
            }
            mantissa = mantissa * 10 + u64::from(c - b'0');
        }
        let exp_negative = match self.byte(first + 6) {
            b'+' => false,
            b'-' => true,
            found => return Err(self.err(first + 6, TleErrorKind::InvalidCharacter { found })),
        };
        let e = self.byte(last);
        if !e.is_ascii_digit() {
            return Err(self.err(last, TleErrorKind::NotDigit { found: e }));
        }
        let e = i32::from(e - b'0');
        let exponent = if exp_negative { -e } else { e };
        // 0.NNNNN · 10^E = NNNNN · 10^(E − 5)
        let magnitude = scaled(mantissa, exponent - 5);
        Ok(Some(if negative { -magnitude } else { magnitude }))
    }

    /// Catalogue number, columns 3–7: right-justified digits, or Alpha-5 (a letter A–Z except
    /// I and O for the ten-thousands digit 10–33, then four digits).
    fn catalog_number(&self) -> Result<u32, TleError> {
        let lead = self.byte(3);
        let ten_thousands = match lead {
            b'A'..=b'H' => Some(u32::from(lead - b'A') + 10),
            b'J'..=b'N' => Some(u32::from(lead - b'J') + 18),
            b'P'..=b'Z' => Some(u32::from(lead - b'P') + 23),
            b'I' | b'O' => return Err(self.err(3, TleErrorKind::InvalidCharacter { found: lead })),
            _ => None,
        };
        match ten_thousands {
            Some(t) => {
                let mut rest = 0_u32;
                for (col, c) in self.columns(4, 7) {
                    if !c.is_ascii_digit() {
                        return Err(self.err(col, TleErrorKind::NotDigit { found: c }));
                    }
                    rest = rest * 10 + u32::from(c - b'0');
                }
                Ok(t * 10_000 + rest)
            }
            None => self.uint(3, 7),
        }
    }
}

/// The 1-based column of a 0-based byte index (saturating).
fn column(index: usize) -> u8 {
    u8::try_from(index + 1).unwrap_or(u8::MAX)
}

/// Line 1 fields other than those of line 2.
struct Line1 {
    catalog_number: u32,
    classification: u8,
    international_designator: heapless::String<8>,
    epoch: Epoch<Utc>,
    mean_motion_dot: f64,
    mean_motion_ddot: f64,
    bstar: f64,
    ephemeris_type: u8,
    element_set_number: u16,
}

fn parse_line1(raw: &str, checksum: Checksum) -> Result<Line1, TleError> {
    let l = DataLine::new(raw, 1)?;
    l.separators(&[2, 9, 18, 33, 44, 53, 62, 64])?;
    let catalog_number = l.catalog_number()?;
    let classification = match l.byte(8) {
        c @ (b'U' | b'C' | b'S') => c,
        b' ' => return Err(l.err(8, TleErrorKind::Blank)),
        found => return Err(l.err(8, TleErrorKind::InvalidCharacter { found })),
    };
    let designator = core::str::from_utf8(l.text.get(9..17).unwrap_or(&[]))
        .map_err(|_| l.err(10, TleErrorKind::NonAscii))?
        .trim();
    let international_designator = heapless::String::try_from(designator)
        .map_err(|_| l.err(10, TleErrorKind::OutOfRange { value: 0.0 }))?;

    // Epoch: YY DDD.DDDDDDDD, read as integers (the fraction in units of 1e-8 day).
    let year = l.uint(19, 20)?;
    let day_of_year = l.uint(21, 23)?;
    match l.byte(24) {
        b'.' => {}
        found => return Err(l.err(24, TleErrorKind::InvalidCharacter { found })),
    }
    let mut fraction_1e8 = 0_u32;
    for (col, c) in l.columns(25, 32) {
        if !c.is_ascii_digit() {
            return Err(l.err(col, TleErrorKind::NotDigit { found: c }));
        }
        fraction_1e8 = fraction_1e8 * 10 + u32::from(c - b'0');
    }
    // year ≤ 99 and day ≤ 999 by their column widths
    let epoch =
        Epoch::from_tle_epoch(year as u8, day_of_year as u16, fraction_1e8).map_err(|_| {
            l.err(
                21,
                TleErrorKind::OutOfRange {
                    value: f64::from(day_of_year),
                },
            )
        })?;

    let mean_motion_dot = l.decimal(34, 43, true)?;
    // n̈/6 is "blank if N/A" (note 003 §2.1); B* is required.
    let mean_motion_ddot = l.exponent_field(45)?.unwrap_or(0.0);
    let bstar = l
        .exponent_field(54)?
        .ok_or_else(|| l.err(54, TleErrorKind::Blank))?;
    let ephemeris_type = l.uint_or_blank(63, 63)?.unwrap_or(0) as u8;
    let element_set_number = l.uint(65, 68)? as u16;
    if checksum == Checksum::Verify {
        l.verify_checksum()?;
    }
    Ok(Line1 {
        catalog_number,
        classification,
        international_designator,
        epoch,
        mean_motion_dot,
        mean_motion_ddot,
        bstar,
        ephemeris_type,
        element_set_number,
    })
}

/// Line 2 fields.
struct Line2 {
    catalog_number: u32,
    inclination_deg: f64,
    raan_deg: f64,
    eccentricity: f64,
    arg_perigee_deg: f64,
    mean_anomaly_deg: f64,
    mean_motion_rev_per_day: f64,
    revolution_number: u32,
}

fn parse_line2(raw: &str, checksum: Checksum) -> Result<Line2, TleError> {
    let l = DataLine::new(raw, 2)?;
    l.separators(&[2, 8, 17, 26, 34, 43, 52])?;
    let catalog_number = l.catalog_number()?;
    let inclination_deg = l.decimal(9, 16, false)?;
    let raan_deg = l.decimal(18, 25, false)?;
    // Eccentricity: seven digits, implied leading "0.".
    if l.is_blank(27, 33) {
        return Err(l.err(27, TleErrorKind::Blank));
    }
    let mut e_1e7 = 0_u64;
    for (col, c) in l.columns(27, 33) {
        if !c.is_ascii_digit() {
            return Err(l.err(col, TleErrorKind::NotDigit { found: c }));
        }
        e_1e7 = e_1e7 * 10 + u64::from(c - b'0');
    }
    let eccentricity = scaled(e_1e7, -7);
    let arg_perigee_deg = l.decimal(35, 42, false)?;
    let mean_anomaly_deg = l.decimal(44, 51, false)?;
    // Signed, so that a negative mean motion is reported as such.
    let mean_motion_rev_per_day = l.decimal(53, 63, true)?;
    let revolution_number = l.uint(64, 68)?;
    if checksum == Checksum::Verify {
        l.verify_checksum()?;
    }
    Ok(Line2 {
        catalog_number,
        inclination_deg,
        raan_deg,
        eccentricity,
        arg_perigee_deg,
        mean_anomaly_deg,
        mean_motion_rev_per_day,
        revolution_number,
    })
}

/// The name line: an optional `"0 "` prefix removed, trimmed, ASCII, at most 24 characters;
/// `None` when empty.
fn parse_name(raw: &str) -> Result<Option<heapless::String<24>>, TleError> {
    let err = |column: usize, kind| TleError {
        line: 0,
        column: self::column(column),
        field: TleField::Name,
        kind,
    };
    if let Some(i) = raw.bytes().position(|b| !b.is_ascii()) {
        return Err(err(i, TleErrorKind::NonAscii));
    }
    let body = raw.strip_prefix("0 ").unwrap_or(raw);
    let name = body.trim();
    if name.len() > NAME_LENGTH {
        // point at the first character beyond the limit
        let offset = (raw.len() - body.len()) + (body.len() - body.trim_start().len());
        return Err(err(
            offset + NAME_LENGTH,
            TleErrorKind::NameTooLong { length: name.len() },
        ));
    }
    if name.is_empty() {
        return Ok(None);
    }
    heapless::String::try_from(name)
        .map(Some)
        .map_err(|_| err(0, TleErrorKind::NameTooLong { length: name.len() }))
}

impl Tle {
    /// Parses a two-line element set (checksums verified), then [`Tle::validate`]s it.
    ///
    /// Each line may carry a trailing `\r` and anything after column 69.
    pub fn parse(line1: &str, line2: &str) -> Result<Self, TleError> {
        Self::parse_with(None, line1, line2, Checksum::Verify)
    }

    /// Parses a three-line element set: a name line (an optional `"0 "` prefix is removed) and
    /// the two data lines.
    pub fn parse_with_name(name: &str, line1: &str, line2: &str) -> Result<Self, TleError> {
        Self::parse_with(Some(name), line1, line2, Checksum::Verify)
    }

    /// Parses with an optional name line and a choice of checksum verification.
    ///
    /// Errors come in this order: line 0, line 1 (columns left to right, checksum last),
    /// line 2 likewise, the catalogue numbers of the two lines, then [`Tle::validate`].
    pub fn parse_with(
        name: Option<&str>,
        line1: &str,
        line2: &str,
        checksum: Checksum,
    ) -> Result<Self, TleError> {
        let name = match name {
            Some(n) => parse_name(n)?,
            None => None,
        };
        let a = parse_line1(line1, checksum)?;
        let b = parse_line2(line2, checksum)?;
        if a.catalog_number != b.catalog_number {
            return Err(TleError::at(
                2,
                3,
                TleErrorKind::SatelliteMismatch {
                    line1: a.catalog_number,
                    line2: b.catalog_number,
                },
            ));
        }
        let tle = Self {
            name,
            catalog_number: a.catalog_number,
            classification: a.classification,
            international_designator: a.international_designator,
            epoch: a.epoch,
            mean_motion_dot: a.mean_motion_dot,
            mean_motion_ddot: a.mean_motion_ddot,
            bstar: a.bstar,
            ephemeris_type: a.ephemeris_type,
            element_set_number: a.element_set_number,
            inclination_deg: b.inclination_deg,
            raan_deg: b.raan_deg,
            eccentricity: b.eccentricity,
            arg_perigee_deg: b.arg_perigee_deg,
            mean_anomaly_deg: b.mean_anomaly_deg,
            mean_motion_rev_per_day: b.mean_motion_rev_per_day,
            revolution_number: b.revolution_number,
        };
        tle.validate()?;
        Ok(tle)
    }

    /// Parses one element set from text: two or three lines after skipping blank lines and
    /// lines starting with `#`. With three lines the first is the name; with two, the first
    /// must be line 1 (if it is not but the second is, line 2 is reported missing).
    pub fn parse_text(text: &str) -> Result<Self, TleError> {
        let mut lines: [&str; 3] = [""; 3];
        let mut count = 0_usize;
        let useful = text.lines().enumerate().filter(|(_, l)| {
            let t = l.trim();
            !t.is_empty() && !t.starts_with('#')
        });
        for (index, line) in useful {
            match lines.get_mut(count) {
                Some(slot) => *slot = line,
                None => {
                    return Err(TleError {
                        line: 2,
                        column: 1,
                        field: TleField::Line,
                        kind: TleErrorKind::ExtraLine {
                            text_line: index + 1,
                        },
                    })
                }
            }
            count += 1;
        }
        let missing = |line: u8| TleError {
            line,
            column: 1,
            field: TleField::Line,
            kind: TleErrorKind::MissingLine,
        };
        match (count, lines) {
            (3, [name, l1, l2]) => Self::parse_with_name(name, l1, l2),
            (2, [l1, l2, _]) if l1.starts_with('1') || !l2.starts_with('1') => Self::parse(l1, l2),
            (2, _) => Err(missing(2)),
            (1, [l1, _, _]) if l1.starts_with('1') => Err(missing(2)),
            _ => Err(missing(1)),
        }
    }

    /// Checks the ranges of the values (also for a hand-built [`Tle`]): 0 ≤ e < 1, a positive
    /// mean motion, inclination in 0..=180°, the other angles in 0..=360°, all values finite.
    /// The error names the TLE column of the field.
    pub fn validate(&self) -> Result<(), TleError> {
        let e = self.eccentricity;
        if !(e >= 0.0) || e >= 1.0 {
            return Err(TleError::at(2, 27, TleErrorKind::Eccentricity { value: e }));
        }
        let n = self.mean_motion_rev_per_day;
        if !(n > 0.0 && n.is_finite()) {
            return Err(TleError::at(
                2,
                53,
                TleErrorKind::MeanMotionNotPositive { value: n },
            ));
        }
        let angles = [
            (9, self.inclination_deg, 180.0),
            (18, self.raan_deg, 360.0),
            (35, self.arg_perigee_deg, 360.0),
            (44, self.mean_anomaly_deg, 360.0),
        ];
        for (col, value, max) in angles {
            if !(value >= 0.0) || value > max {
                return Err(TleError::at(2, col, TleErrorKind::OutOfRange { value }));
            }
        }
        let drag = [
            (34, self.mean_motion_dot),
            (45, self.mean_motion_ddot),
            (54, self.bstar),
        ];
        for (col, value) in drag {
            if !value.is_finite() {
                return Err(TleError::at(1, col, TleErrorKind::OutOfRange { value }));
            }
        }
        Ok(())
    }
}
