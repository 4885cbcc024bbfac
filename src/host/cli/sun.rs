//! `acs sun`: Sun direction for UTC timestamps.

use super::CliError;

/// Arguments of `acs sun`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Sun model.
    #[arg(long, value_parser = ["thesis", "precise"], default_value = "precise")]
    model: String,
    /// Output frame (the `precise` model only).
    #[arg(long, value_parser = ["teme", "j2000"], default_value = "teme")]
    frame: String,
}

/// Runs `acs sun`.
pub fn run(_args: &Args) -> Result<(), CliError> {
    Err(CliError::NotImplemented("sun"))
}
