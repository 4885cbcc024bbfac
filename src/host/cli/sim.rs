//! `acs sim`: closed-loop simulation scenarios.

use super::CliError;

/// Arguments of `acs sim`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Built-in scenario name or scenario file.
    scenario: String,
    /// Output folder for CSV and SVG files.
    #[arg(long)]
    out: Option<std::path::PathBuf>,
}

/// Runs `acs sim`.
pub fn run(_args: &Args) -> Result<(), CliError> {
    Err(CliError::NotImplemented("sim"))
}
