//! Two-line element sets: a column-exact parser with checksum verification (notes 000 §3.3, 003 §2.1).
//!
//! `no_std`, no allocation. Every malformed input gives a [`TleError`] naming the line, the
//! 1-based column and the field.

use crate::time::{Epoch, Utc};

/// A parsed element set, with the values exactly as the TLE states them (mean elements in the
/// TEME frame of the epoch, Kozai mean motion as the format defines).
///
/// The angle and mean-motion fields are f64: the parse is a one-time operation and the eighth
/// decimal of the mean motion matters (a relative error of 6e-8, f32's, is 120 m after 3 days).
#[derive(Clone, Debug, PartialEq)]
pub struct Tle {
    /// The optional name line ("line 0"), trimmed, at most 24 characters.
    pub name: Option<heapless::String<24>>,
    /// NORAD catalogue number (line 1 columns 3–7; Alpha-5 letters are accepted).
    pub catalog_number: u32,
    /// Classification (line 1 column 8): `U`, `C` or `S`.
    pub classification: u8,
    /// International designator (line 1 columns 10–17), trimmed.
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
