//! `acs propagate`: SGP4 ephemeris of a TLE as an STK `.e` file (`docs/cli.md`).
//!
//! The TLE file is parsed with [`Tle::parse_text`] (checksums verified); the propagation is the
//! flight [`Sgp4`] (f32); the optional J2000 output rotates each f32 TEME state with the f64
//! [`crate::frames::teme_to_j2000`] at the row's TT epoch (UTC + ΔAT + 32.184 s, leap seconds
//! extrapolated past the table).
//!
//! Exit codes: 2 for an unreadable or malformed TLE file or bad times (non-finite, step ≤ 0,
//! stop before start, more than [`MAX_ROWS`] rows, beyond ±3·10⁷ min); 3 when SGP4 refuses the
//! element set (deep space, sub-orbital, …) or fails part-way (decay, eccentricity out of
//! range), in which case the rows before the failure are written as a complete file first.

use std::io::Write;

use super::CliError;
use crate::host::stk::{self, CoordinateSystem, StateRow, StkEphemeris};
use crate::orbit::sgp4::{Gravity, Sgp4, Sgp4Error};
use crate::orbit::TemeState;
use crate::time::{Epoch, TimeSpan, Utc};
use crate::tle::Tle;

/// Most rows one run may write (a week at a 0.1 s step is 6 million).
pub const MAX_ROWS: u64 = 10_000_000;

/// Arguments of `acs propagate`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// File with one element set (two lines, or a name line and two lines).
    #[arg(long)]
    tle: std::path::PathBuf,
    /// First output time, minutes from the TLE epoch.
    #[arg(long, allow_negative_numbers = true)]
    start: f64,
    /// Last output time, minutes from the TLE epoch.
    #[arg(long, allow_negative_numbers = true)]
    stop: f64,
    /// Output step, minutes.
    #[arg(long)]
    step: f64,
    /// Gravity model.
    #[arg(long, value_parser = ["wgs72", "wgs84"], default_value = "wgs72")]
    gravity: String,
    /// Output frame.
    #[arg(long, value_parser = ["teme", "j2000"], default_value = "teme")]
    frame: String,
}

/// The number of rows of `start..=stop` by `step` (minutes), validated.
fn row_count(start: f64, stop: f64, step: f64) -> Result<u64, CliError> {
    if !(start.is_finite() && stop.is_finite() && step.is_finite()) {
        return Err(CliError::Input(
            "--start, --stop and --step must be finite numbers".into(),
        ));
    }
    if step <= 0.0 {
        return Err(CliError::Input(format!("--step {step} must be positive")));
    }
    if stop < start {
        return Err(CliError::Input(format!(
            "--stop {stop} is before --start {start}"
        )));
    }
    // a tolerance of 1e-9 step so that 0..=60 by 5 includes 60
    let count = ((stop - start) / step + 1e-9).floor() + 1.0;
    if count > MAX_ROWS as f64 {
        return Err(CliError::Input(format!(
            "{count} rows requested, at most {MAX_ROWS}: increase --step"
        )));
    }
    Ok(count as u64)
}

/// Reads the one element set of a TLE file ([`Tle::parse_text`], checksums verified): exit 2
/// naming the file and the parser's [`crate::tle::TleError`] (line, column, field).
pub(super) fn read_tle(path: &std::path::Path) -> Result<Tle, CliError> {
    let name = path.display();
    let text =
        std::fs::read_to_string(path).map_err(|e| CliError::Input(format!("{name}: {e}")))?;
    Tle::parse_text(&text).map_err(|e| CliError::Input(format!("{name}: {e}")))
}

/// The `--gravity` value (`wgs72` or `wgs84`, checked by clap) as a [`Gravity`].
pub(super) fn gravity(name: &str) -> Gravity {
    match name {
        "wgs84" => Gravity::Wgs84,
        _ => Gravity::Wgs72,
    }
}

/// SGP4 initialised for the element set of `path`: exit 2 for an element out of range
/// ([`Sgp4Error::Element`]), 3 when SGP4 refuses the set (deep space, sub-orbital, …).
pub(super) fn init_sgp4(
    tle: &Tle,
    gravity: Gravity,
    path: &std::path::Path,
) -> Result<Sgp4, CliError> {
    let path = path.display();
    Sgp4::new(tle, gravity).map_err(|e| match e {
        Sgp4Error::Element { .. } => CliError::Input(format!("{path}: {e}")),
        _ => CliError::Compute(format!("{path}: {e}")),
    })
}

/// Runs `acs propagate`.
pub fn run(args: &Args) -> Result<(), CliError> {
    let tle = read_tle(&args.tle)?;
    let count = row_count(args.start, args.stop, args.step)?;
    let gravity = gravity(&args.gravity);
    let j2000 = args.frame == "j2000";
    let sgp4 = init_sgp4(&tle, gravity, &args.tle)?;

    let frame = if j2000 {
        CoordinateSystem::J2000
    } else {
        CoordinateSystem::TemeOfDate
    };
    let mut ephemeris = StkEphemeris::new(tle.epoch, frame);
    ephemeris.comments.push(format!(
        "acs propagate: SGP4 {}, NORAD {}; t in seconds from the TLE epoch (= ScenarioEpoch)",
        match gravity {
            Gravity::Wgs72 => "WGS72",
            Gravity::Wgs84 => "WGS84",
        },
        tle.catalog_number
    ));
    let mut failure = None;
    for k in 0..count {
        let t_min = args.start + k as f64 * args.step;
        let span = TimeSpan::from_minutes_f64(t_min)
            .map_err(|e| CliError::Input(format!("time {t_min} min: {e}")))?;
        match sgp4.propagate(span) {
            Ok(state) => {
                let state = if j2000 {
                    to_j2000(&state, &tle.epoch.add(span))?
                } else {
                    to_f64(&state)
                };
                ephemeris.rows.push(StateRow {
                    t_s: span.as_seconds_f64(),
                    r_m: state.0.map(|x| x * 1e3),
                    v_mps: state.1.map(|x| x * 1e3),
                });
            }
            Err(e) => {
                failure = Some(e);
                break;
            }
        }
    }

    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    out.write_all(stk::write(&ephemeris).as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| CliError::Compute(format!("cannot write the output: {e}")))?;
    match failure {
        Some(e) => Err(CliError::Compute(e.to_string())),
        None => Ok(()),
    }
}

/// An f32 TEME state as f64 `(r_km, v_kmps)`.
fn to_f64(s: &TemeState) -> ([f64; 3], [f64; 3]) {
    let r = s.r_teme_km;
    let v = s.v_teme_kmps;
    (
        [f64::from(r.x), f64::from(r.y), f64::from(r.z)],
        [f64::from(v.x), f64::from(v.y), f64::from(v.z)],
    )
}

/// A TEME state rotated to J2000 at the UTC epoch `utc` (f64 rotation).
fn to_j2000(s: &TemeState, utc: &Epoch<Utc>) -> Result<([f64; 3], [f64; 3]), CliError> {
    let tt = utc.to_tt_extrapolated().map_err(|e| {
        CliError::Compute(format!("J2000 output needs the TT epoch of the row: {e}"))
    })?;
    let (r, v) = to_f64(s);
    let (r, v) = crate::frames::teme_to_j2000::<f64>(
        &nalgebra::Vector3::from(r),
        &nalgebra::Vector3::from(v),
        &tt,
    );
    Ok(([r.x, r.y, r.z], [v.x, v.y, v.z]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn row_counts() {
        assert_eq!(row_count(0.0, 60.0, 5.0).ok(), Some(13));
        assert_eq!(row_count(-1440.0, 4320.0, 10.0).ok(), Some(577));
        assert_eq!(row_count(0.0, 0.0, 1.0).ok(), Some(1));
        assert!(matches!(row_count(0.0, 1.0, 0.0), Err(CliError::Input(_))));
        assert!(matches!(row_count(1.0, 0.0, 1.0), Err(CliError::Input(_))));
        assert!(matches!(
            row_count(f64::NAN, 0.0, 1.0),
            Err(CliError::Input(_))
        ));
        assert!(matches!(row_count(0.0, 1e9, 1e-3), Err(CliError::Input(_))));
    }
}
