//! `acs propagate`: SGP4 ephemeris of a TLE as an STK `.e` file.

use super::CliError;

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

/// Runs `acs propagate`.
pub fn run(_args: &Args) -> Result<(), CliError> {
    Err(CliError::NotImplemented("propagate"))
}
